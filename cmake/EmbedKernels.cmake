# facetool_embed_kernels(OUT_CPP NAMESPACE ns FILES a.cl b.cl): embeds OpenCL sources as strings.
#
# Generates OUT_CPP defining, in namespace NS,
#   const char* kernel_source(const std::string& file_name);   // nullptr if unknown
# so the kernels in kernels/*.cl ship inside the binary and never need to be found on disk.
function(facetool_embed_kernels out_cpp)
  cmake_parse_arguments(EMBED "" "NAMESPACE" "FILES" ${ARGN})
  set(script ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/embed_kernels_script.cmake)
  add_custom_command(
    OUTPUT ${out_cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out_cpp} -DNAMESPACE=${EMBED_NAMESPACE}
            "-DFILES=${EMBED_FILES}" -P ${script}
    DEPENDS ${EMBED_FILES} ${script}
    COMMENT "Embedding OpenCL kernels into ${out_cpp}"
    VERBATIM)
endfunction()
