# facetool_add_plugin(name SOURCES src...): a facetool plugin, <name>.ftplugin.so, from its sources.
#
# One definition for the plugins shipped with facetool and for third parties building against an
# installed SDK (find_package(facetool CONFIG) includes this file): the module is linked to
# facetool::core, named as the loader expects, and compiled with hidden visibility so that only
# facetool_plugin_entry (FACETOOL_DEFINE_PLUGIN) is exported. `facetool_add_plugin(name a.cpp ...)`
# without SOURCES is accepted too.
function(facetool_add_plugin name)
  cmake_parse_arguments(PLUGIN "" "" "SOURCES" ${ARGN})
  if(NOT PLUGIN_SOURCES)
    set(PLUGIN_SOURCES ${PLUGIN_UNPARSED_ARGUMENTS})
  endif()
  add_library(${name} MODULE ${PLUGIN_SOURCES})
  target_link_libraries(${name} PRIVATE facetool::core)
  target_compile_features(${name} PRIVATE cxx_std_17)
  set_target_properties(${name} PROPERTIES PREFIX "" SUFFIX ".ftplugin.so"
                        CXX_VISIBILITY_PRESET hidden)
  if(COMMAND facetool_warnings)
    facetool_warnings(${name})
  endif()
endfunction()
