# cmake -DFOLDER=dir -DMAY_USE=a,b -DFORBIDDEN_THIRD_PARTY=x,y [-DFORBIDDEN_HEADERS=m/h.hpp,...] -DSTAMP=file
#       -P check_layering.cmake
# Fails, naming every offending line, when a .cpp or .hpp of FOLDER includes "module/..." for a
# module outside MAY_USE, <library/...> for a library in FORBIDDEN_THIRD_PARTY, or "module/header"
# in FORBIDDEN_HEADERS. The generated "settle/..." headers and includes without a folder are always
# allowed. Writes STAMP on success.
cmake_minimum_required(VERSION 3.25)
string(REPLACE "," ";" may_use "${MAY_USE}")
string(REPLACE "," ";" forbidden "${FORBIDDEN_THIRD_PARTY}")
string(REPLACE "," ";" forbidden_headers "${FORBIDDEN_HEADERS}")
get_filename_component(module "${FOLDER}" NAME)
file(GLOB files "${FOLDER}/*.cpp" "${FOLDER}/*.hpp")
set(violations "")
foreach(file IN LISTS files)
  get_filename_component(file_name "${file}" NAME)
  file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"][^/>\"]+/")
  foreach(line IN LISTS includes)
    string(REGEX MATCH "[<\"]([^/>\"]+)/" _ "${line}")
    set(first_part "${CMAKE_MATCH_1}")
    string(REGEX MATCH "\"([^\"]+)\"" _ "${line}")
    set(quoted_path "${CMAKE_MATCH_1}")
    if(line MATCHES "\"" AND NOT first_part STREQUAL "settle" AND NOT first_part IN_LIST may_use)
      string(APPEND violations "\n  src/${module}/${file_name}: ${line}  (${module} may use: ${MAY_USE})")
    elseif(line MATCHES "\"" AND quoted_path IN_LIST forbidden_headers)
      string(APPEND violations "\n  src/${module}/${file_name}: ${line}  (${quoted_path} is restricted to the modules "
                               "naming it under HEADERS in src/CMakeLists.txt)")
    elseif(line MATCHES "<" AND first_part IN_LIST forbidden)
      string(APPEND violations "\n  src/${module}/${file_name}: ${line}  (${first_part} is not among ${module}'s libraries)")
    endif()
  endforeach()
endforeach()
if(violations)
  message(FATAL_ERROR "Layering (docs/architecture.md, \"Who may use whom\"; the table in src/CMakeLists.txt):"
                      "${violations}")
endif()
file(WRITE "${STAMP}" "")
