# Fails if a file of the dataflow engine (cpp/src/graph, cpp/include/mereo/graph) includes a
# header of another mereo module: the engine may include mereo/graph/... and outside libraries
# only; the library registers its port types and node kinds into it (mereo/nodes/builtin.hpp).
#   cmake -DROOT=<source dir> -P tests/check_engine_includes.cmake
file(GLOB_RECURSE files ${ROOT}/cpp/src/graph/* ${ROOT}/cpp/include/mereo/graph/*)
if(NOT files)
  message(FATAL_ERROR "no engine files under ${ROOT}")
endif()
set(bad "")
foreach(f ${files})
  file(STRINGS ${f} includes REGEX "^[ \t]*#[ \t]*include")
  foreach(line ${includes})
    string(REGEX MATCH "[\"<]([^\">]+)[\">]" _ "${line}")
    set(path "${CMAKE_MATCH_1}")
    # quoted: only the engine's own headers; <...>: no mereo header but the engine's
    if((line MATCHES "\"" AND NOT path MATCHES "^mereo/graph/") OR (path MATCHES "^mereo/" AND NOT path MATCHES "^mereo/graph/"))
      string(APPEND bad "\n  ${f}: ${line}")
    endif()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "the engine includes headers of other modules:${bad}")
endif()
list(LENGTH files n)
message(STATUS "${n} engine files include only mereo/graph/ headers and outside libraries")
