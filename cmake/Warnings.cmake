# facetool_warnings(target): the project's warning flags (-Wall -Wextra, clean by policy).
function(facetool_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if(FACETOOL_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
