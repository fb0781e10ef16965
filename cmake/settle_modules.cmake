# The modules of libsettle and the check of who may use whom (src/CMakeLists.txt has the table).

# Third-party libraries that only the modules naming them may include (by the include's first path
# part). Eigen, fmt and OpenMP are everyone's.
set(SETTLE_RESTRICTED_THIRD_PARTY toml++ nlohmann CLI)
# Headers (by their path under src/) that only their own module and the modules naming them under
# HEADERS may include, although others use that module: the exchange protocol of a block of a split
# lattice, which only parallel drives (docs/parallel.md).
set(SETTLE_RESTRICTED_HEADERS lbm/block_exchange.hpp)

# settle_add_module(NAME [USES module...] [THIRD_PARTY library...] [HEADERS restricted header...]): the
# static library settle_NAME of every .cpp in src/NAME, linking the modules it USES (each of which
# brings the modules it may use in turn), and the layering check of its folder.
function(settle_add_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "USES;THIRD_PARTY;HEADERS")
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${name}/*.cpp)
  add_library(settle_${name} STATIC ${sources})
  target_link_libraries(settle_${name} PUBLIC settle_options PRIVATE settle_instrument)
  set(may_use ${name})
  foreach(used IN LISTS arg_USES)
    target_link_libraries(settle_${name} PUBLIC settle_${used})
    get_property(used_may_use GLOBAL PROPERTY settle_may_use_${used})
    list(APPEND may_use ${used_may_use})
  endforeach()
  list(REMOVE_DUPLICATES may_use)
  set_property(GLOBAL PROPERTY settle_may_use_${name} ${may_use})
  set_property(GLOBAL APPEND PROPERTY settle_modules ${name})
  settle_add_layering_check(${name} MAY_USE ${may_use} THIRD_PARTY ${arg_THIRD_PARTY} HEADERS ${arg_HEADERS})
  add_dependencies(settle_${name} settle_${name}_layering)
endfunction()

# settle_add_layering_check(FOLDER [MAY_USE module...] [THIRD_PARTY library...] [HEADERS header...]): the
# target settle_FOLDER_layering, which fails when a file of src/FOLDER includes a module outside
# MAY_USE (all modules when MAY_USE is empty), a restricted library outside THIRD_PARTY, or a
# restricted header of another module outside HEADERS. It runs again whenever a file of the folder
# changes.
function(settle_add_layering_check folder)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "MAY_USE;THIRD_PARTY;HEADERS")
  if(NOT arg_MAY_USE)
    get_property(arg_MAY_USE GLOBAL PROPERTY settle_modules)
    list(APPEND arg_MAY_USE ${folder})
  endif()
  set(forbidden_third_party ${SETTLE_RESTRICTED_THIRD_PARTY})
  if(arg_THIRD_PARTY)
    list(REMOVE_ITEM forbidden_third_party ${arg_THIRD_PARTY})
  endif()
  set(forbidden_headers ${SETTLE_RESTRICTED_HEADERS})
  list(FILTER forbidden_headers EXCLUDE REGEX "^${folder}/")
  if(arg_HEADERS)
    list(REMOVE_ITEM forbidden_headers ${arg_HEADERS})
  endif()
  file(GLOB files CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.cpp ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.hpp)
  list(JOIN arg_MAY_USE "," may_use)
  list(JOIN forbidden_third_party "," forbidden)
  list(JOIN forbidden_headers "," forbidden_headers)
  set(stamp ${CMAKE_CURRENT_BINARY_DIR}/layering_${folder}.stamp)
  add_custom_command(OUTPUT ${stamp}
    COMMAND ${CMAKE_COMMAND} -DFOLDER=${CMAKE_CURRENT_SOURCE_DIR}/${folder} -DMAY_USE=${may_use}
            -DFORBIDDEN_THIRD_PARTY=${forbidden} -DFORBIDDEN_HEADERS=${forbidden_headers} -DSTAMP=${stamp}
            -P ${PROJECT_SOURCE_DIR}/cmake/check_layering.cmake
    DEPENDS ${files} ${PROJECT_SOURCE_DIR}/cmake/check_layering.cmake
    COMMENT "Checking the includes of src/${folder} against the modules it may use"
    VERBATIM)
  add_custom_target(settle_${folder}_layering DEPENDS ${stamp})
endfunction()
