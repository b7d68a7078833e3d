# Installation and packaging: the program, libfacetool_core, libfacetool (the libraries above the
# core: photos, decomposition, relighting, training), the shipped plugins and backend modules, the
# models, and the SDK (headers, CMake package, pkg-config); cpack -G DEB makes the packages
# facetool (runtime) and facetool-dev (the SDK). Layout under the prefix:
#   bin/facetool  lib/libfacetool_core.so  lib/libfacetool.so  lib/facetool/<backend modules, the OpenImageIO module>
#   lib/facetool/plugins/*.ftplugin.so  share/facetool/models/  share/facetool/lights/  share/facetool/dlib/ (dlib's HOG
#   face detector decoded at build time and its landmark model as plain arrays:
#   libs/face/CMakeLists.txt)  include/facetool/{core,libs}/...
#   lib/cmake/facetool/  lib/pkgconfig/facetool.pc
# The loaders search relative to the executable and to libfacetool_core, so a prefix works
# wherever it is unpacked (RPATHs are $ORIGIN-relative).
include(CMakePackageConfigHelpers)

# The public headers: what a plugin needs (tensors, the op table's interface and op parameters,
# ops, autograd, plugin interfaces and loader, the SH library, errors). Nothing of the backends'
# internals; scripts/check-sdk.sh compiles each one alone against the installed prefix.
set(FACETOOL_PUBLIC_HEADERS
  core/tensor/shape.h core/tensor/tensor.h
  core/backend/backend.h core/backend/custom_kernel.h core/backend/op_params.h
  core/backend/registry.h
  core/ops/ops.h
  core/autograd/variable.h core/autograd/functions.h
  core/plugin/plugin_api.h core/plugin/plugin.h core/plugin/network_plugin.h
  core/plugin/renderer_plugin.h core/plugin/loss_plugin.h core/plugin/renderer_autograd.h
  core/plugin/plugin_loader.h core/plugin/plugin_descriptor.h
  core/sh/sh_types.h core/sh/sh_basis.h core/sh/sh_eval.h core/sh/sh_projection.h
  core/sh/sh_rotation.h core/sh/sh_gram.h core/sh/triple_product.h core/sh/clamped_cosine.h
  core/sh/illumination_from_shading.h core/sh/light_clamp.h core/sh/envmap_projection.h
  core/sh/sphere_samples.h core/sh/pixel_transfer.h
  core/util/error.h core/util/math_constants.h core/util/atomic_file.h core/util/folder_lock.h)
# The C++ API (facetool::facetool, docs/api.md): the headers of every library above the core,
# except those that include a third-party header;
# the core headers they include are among the plugin SDK's above. check-sdk.sh compiles each alone.
get_property(api_libraries GLOBAL PROPERTY FACETOOL_LIBRARIES)
set(api_headers "")
foreach(library ${api_libraries})
  get_target_property(dir ${library} SOURCE_DIR)
  file(GLOB headers ${dir}/*.h)
  list(APPEND api_headers ${headers})
endforeach()
foreach(header ${api_headers})
  file(STRINGS ${header} third_party REGEX "#include <(OpenImageIO|embree|dlib|mpi|boost|nlohmann)")
  if(third_party)
    continue()
  endif()
  file(RELATIVE_PATH relative ${PROJECT_SOURCE_DIR} ${header})
  list(APPEND FACETOOL_PUBLIC_HEADERS ${relative})
endforeach()
list(REMOVE_DUPLICATES FACETOOL_PUBLIC_HEADERS)
foreach(header ${FACETOOL_PUBLIC_HEADERS})
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/${header} DESTINATION include/facetool/${dir}
          COMPONENT dev)
endforeach()

# Runtime: program, core library, backend modules (plugins: plugins/CMakeLists.txt).
set_target_properties(facetool PROPERTIES INSTALL_RPATH "$ORIGIN/../lib")
set_target_properties(facetool_core PROPERTIES INSTALL_RPATH "$ORIGIN" EXPORT_NAME core)
install(TARGETS facetool RUNTIME DESTINATION bin COMPONENT runtime)
install(TARGETS facetool_core EXPORT facetoolTargets
        LIBRARY DESTINATION lib COMPONENT runtime)
set_target_properties(facetool_api PROPERTIES INSTALL_RPATH "$ORIGIN")
install(TARGETS facetool_api EXPORT facetoolTargets LIBRARY DESTINATION lib COMPONENT runtime)
# The OpenImageIO module (libs/io/openimageio), found where the backend modules are.
set_target_properties(facetool_openimageio PROPERTIES INSTALL_RPATH "$ORIGIN/..:$ORIGIN")
install(TARGETS facetool_openimageio LIBRARY DESTINATION lib/facetool COMPONENT runtime)
if(TARGET facetool_backend_opencl)
  set_target_properties(facetool_backend_opencl PROPERTIES INSTALL_RPATH "$ORIGIN/..")
  install(TARGETS facetool_backend_opencl LIBRARY DESTINATION lib/facetool COMPONENT runtime)
endif()
# The shipped model (models/*.safetensors), which infer, relight, pseudo-label and eval load by default.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/models/ DESTINATION share/facetool/models
        COMPONENT runtime FILES_MATCHING PATTERN "*.safetensors" PATTERN "README.md")
# The shipped light files (lights/*.json: the SH lights of CC0 HDR maps, scripts/make-lights.sh),
# for `relight --light`; the view page embeds them as presets at build time.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lights/ DESTINATION share/facetool/lights
        COMPONENT runtime FILES_MATCHING PATTERN "*.json" PATTERN "README.md")
# dlib's HOG face detector as the build decoded it, and the copy of its landmark model when the
# build had the model to copy (libs/face/CMakeLists.txt).
install(FILES ${CMAKE_BINARY_DIR}/share/facetool/dlib/frontal_face_detector.dat
        DESTINATION share/facetool/dlib COMPONENT runtime)
install(FILES ${CMAKE_BINARY_DIR}/share/facetool/dlib/shape_predictor_68_face_landmarks.copy
        DESTINATION share/facetool/dlib COMPONENT runtime OPTIONAL)

# The SDK: CMake package (facetool::core, facetool::facetool, facetool_add_plugin,
# facetool_embed_kernels), pkg-config (facetool: the core; facetool-api: libfacetool).
set(cmake_dir lib/cmake/facetool)
install(EXPORT facetoolTargets NAMESPACE facetool:: FILE facetoolTargets.cmake
        DESTINATION ${cmake_dir} COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/facetoolConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/facetoolConfig.cmake INSTALL_DESTINATION ${cmake_dir})
# 0.x: a minor version may change the plugin API, so only the same major.minor is compatible.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/facetoolConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/facetoolConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/facetoolConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FacetoolPlugin.cmake
              ${PROJECT_SOURCE_DIR}/cmake/EmbedKernels.cmake
              ${PROJECT_SOURCE_DIR}/cmake/embed_kernels_script.cmake
        DESTINATION ${cmake_dir} COMPONENT dev)
configure_file(${PROJECT_SOURCE_DIR}/cmake/facetool.pc.in ${CMAKE_CURRENT_BINARY_DIR}/facetool.pc
               @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/facetool.pc DESTINATION lib/pkgconfig COMPONENT dev)

# Debian packages: facetool (runtime) and facetool-dev (SDK, depends on facetool).
set(CPACK_PACKAGE_NAME facetool)
set(CPACK_PACKAGE_VENDOR "facetool")
set(CPACK_PACKAGE_CONTACT "facetool maintainers <facetool@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "intrinsic face decomposition (albedo, normals, SH visibility, light) from one photo")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_COMPONENT_DEV_DEPENDS runtime)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME facetool)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME facetool-dev)
set(CPACK_DEBIAN_RUNTIME_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_DEV_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION science)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
# The runtime's library dependencies from dpkg-shlibdeps; the SDK needs a compiler and CMake.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${FACETOOL_OUTPUT_DIR})
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "g++ (>= 4:12), cmake (>= 3.22)")
include(CPack)
