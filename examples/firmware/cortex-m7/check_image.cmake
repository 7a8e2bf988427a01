# cmake -DNM=... -DSIZE=... -DFILES="lib.a;image.elf" -P check_image.cmake
#
# Prints the .text/.data/.bss sizes of each file and fails if any of them
# defines or references a heap function, operator new/delete, a C++
# exception-handling or unwinding routine, RTTI, or a guarded static: what a firmware build of
# neurov promises not to contain.
set(forbidden
  "^(malloc|free|calloc|realloc|memalign|aligned_alloc|posix_memalign|valloc|pvalloc)$"
  "^_(malloc|free|calloc|realloc|memalign)_r$"
  "^_sbrk(_r)?$"
  "^_Zn[wa]"                # operator new, new[]
  "^_Zd[la]"                # operator delete, delete[]
  "^__cxa_(allocate_exception|free_exception|throw|rethrow|begin_catch|end_catch|call_unexpected|get_exception_ptr|current_exception_type)$"
  "^__gxx_personality"
  "^_Unwind_"
  "^__aeabi_unwind_cpp_pr"
  "^_ZTI"                   # typeinfo (RTTI)
  "^__cxa_guard_"           # thread-safe statics: the C++ runtime a C image lacks
)

set(failed FALSE)
foreach(file IN LISTS FILES)
  execute_process(COMMAND "${SIZE}" -t "${file}" OUTPUT_VARIABLE sizes RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${SIZE} failed on ${file}")
  endif()
  message(STATUS "sizes of ${file} (arm-none-eabi-size -t):\n${sizes}")
  execute_process(COMMAND "${NM}" -A "${file}" OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} failed on ${file}")
  endif()
  string(REPLACE "\n" ";" lines "${symbols}")
  set(hits "")
  foreach(line IN LISTS lines)
    # "file:object: [address] TYPE name"; the name is the last field.
    string(REGEX MATCH "[^ ]+$" name "${line}")
    foreach(pattern IN LISTS forbidden)
      if(name MATCHES "${pattern}")
        list(APPEND hits "${line}")
      endif()
    endforeach()
  endforeach()
  if(hits)
    list(JOIN hits "\n  " shown)
    message(SEND_ERROR "${file}: forbidden symbols (heap, new/delete, exceptions or RTTI):\n  ${shown}")
    set(failed TRUE)
  else()
    message(STATUS "${file}: no heap, operator new/delete, exception-handling or RTTI symbols")
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "symbol check failed")
endif()
