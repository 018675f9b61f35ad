# brdfbake_warnings(target): the warning set every target of ours compiles with.
function(brdfbake_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wconversion -Wsign-conversion -Wdouble-promotion -Wshadow -Wpedantic)
  if(BRDFBAKE_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# The floating-point model of code that must match a reference exactly: no contraction, no fast-math.
function(brdfbake_strict_fp target)
  target_compile_options(${target} PRIVATE -ffp-contract=off -fno-fast-math)
endfunction()
