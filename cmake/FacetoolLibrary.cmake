# facetool_add_library(name SOURCES ... [DEPENDS ...]): one library above the compute core.
#
# The layers above libfacetool_core (I/O, lights, models, synthesis, data, faces, ranks, training,
# inference, relighting) are static libraries linked into the facetool program and the tests;
# each sits in its own folder under core/ and links only what it needs (docs/architecture.md).
# `facetool_libraries` (an interface target made by facetool_finish_libraries) links all of them.
function(facetool_add_library name)
  cmake_parse_arguments(LIB "" "" "SOURCES;DEPENDS" ${ARGN})
  add_library(${name} STATIC ${LIB_SOURCES})
  target_link_libraries(${name} PUBLIC facetool_core ${LIB_DEPENDS})
  target_link_libraries(${name} PRIVATE nlohmann_json::nlohmann_json)
  facetool_warnings(${name})
  set_property(GLOBAL APPEND PROPERTY FACETOOL_LIBRARIES ${name})
endfunction()

# facetool_finish_libraries(): the interface target `facetool_libraries` (every library above the
# core, for the program and the tests), after every facetool_add_library call.
function(facetool_finish_libraries)
  get_property(libraries GLOBAL PROPERTY FACETOOL_LIBRARIES)
  add_library(facetool_libraries INTERFACE)
  target_link_libraries(facetool_libraries INTERFACE facetool_core ${libraries})
endfunction()
