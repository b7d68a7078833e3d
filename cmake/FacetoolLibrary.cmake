# facetool_add_library(name SOURCES ... [DEPENDS ...]): one library above the compute core.
#
# The layers above libfacetool_core (I/O, lights, models, synthesis, data, faces, ranks, training,
# inference, relighting) are static libraries linked into the facetool program and the tests;
# each sits in its own folder under libs/ and links only what it needs (docs/architecture.md).
# `facetool_libraries` (an interface target made by facetool_finish_libraries) links all of them.
function(facetool_add_library name)
  cmake_parse_arguments(LIB "" "" "SOURCES;DEPENDS" ${ARGN})
  add_library(${name} STATIC ${LIB_SOURCES})
  target_link_libraries(${name} PUBLIC facetool_core ${LIB_DEPENDS})
  target_link_libraries(${name} PRIVATE nlohmann_json::nlohmann_json)
  facetool_warnings(${name})
  set_property(GLOBAL APPEND PROPERTY FACETOOL_LIBRARIES ${name})
  # What it declares it may use (tests/layering checks every #include against it).
  set_property(TARGET ${name} PROPERTY FACETOOL_DEPENDS ${LIB_DEPENDS})
endfunction()

# facetool_finish_libraries(), after every facetool_add_library call:
# - `facetool_libraries`, an interface target linking every library above the core (for the
#   program and the tests);
# - `facetool_api` (libfacetool.so, installed as facetool::facetool): the same libraries in one
#   shared library for programs that use facetool (decomposition, relighting, training); their own
#   dependencies (OpenImageIO, dlib, Embree, MPI) stay private to it, so a user needs only
#   facetool::core's headers and these libraries' headers.
function(facetool_finish_libraries)
  get_property(libraries GLOBAL PROPERTY FACETOOL_LIBRARIES)
  add_library(facetool_libraries INTERFACE)
  target_link_libraries(facetool_libraries INTERFACE facetool_core ${libraries})

  # Every object of every library (so nothing is left out for a user), and the libraries again
  # for their own dependencies (their objects are already in).
  set(objects "")
  foreach(library ${libraries})
    list(APPEND objects $<TARGET_OBJECTS:${library}>)
  endforeach()
  add_library(facetool_api SHARED ${PROJECT_SOURCE_DIR}/cmake/facetool_api.cpp ${objects})
  target_link_libraries(facetool_api PUBLIC facetool_core)
  target_link_libraries(facetool_api PRIVATE ${libraries})
  set_target_properties(facetool_api PROPERTIES OUTPUT_NAME facetool EXPORT_NAME facetool)
  if(NOT CMAKE_CXX_FLAGS MATCHES "sanitize")
    target_link_options(facetool_api PRIVATE -Wl,--no-undefined)
  endif()

endfunction()

# facetool_write_layers(), once every library and backend has its sources: <build>/facetool_layers.txt,
# one line per library: its name, its folders (from its sources, so the check follows the folders
# wherever they move) and the libraries it declares; tests/layering checks the includes against it.
function(facetool_write_layers)
  get_property(libraries GLOBAL PROPERTY FACETOOL_LIBRARIES)
  set(lines "# name|folders|declared libraries (written by cmake/FacetoolLibrary.cmake)\n")
  foreach(target facetool_core ${libraries})
    get_target_property(sources ${target} SOURCES)
    get_target_property(source_dir ${target} SOURCE_DIR)
    set(dirs "")
    foreach(source ${sources})
      get_filename_component(absolute ${source} ABSOLUTE BASE_DIR ${source_dir})
      get_filename_component(dir ${absolute} DIRECTORY)
      file(RELATIVE_PATH dir ${PROJECT_SOURCE_DIR} ${dir})
      list(APPEND dirs ${dir})
    endforeach()
    list(REMOVE_DUPLICATES dirs)
    get_target_property(depends ${target} FACETOOL_DEPENDS)
    if(NOT depends)
      set(depends "")
    endif()
    string(REPLACE ";" " " dirs "${dirs}")
    string(REPLACE ";" " " depends "${depends}")
    string(APPEND lines "${target}|${dirs}|${depends}\n")
  endforeach()
  file(WRITE ${CMAKE_BINARY_DIR}/facetool_layers.txt "${lines}")
endfunction()
