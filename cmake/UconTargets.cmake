# Project-wide helpers: warnings and language level for project targets only (no global flags).

function(ucon_configure_target target)
  target_compile_features(${target} PRIVATE cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wno-unused-parameter)
endfunction()

# ucon_library(name SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
function(ucon_library name)
  cmake_parse_arguments(A "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} STATIC ${A_SOURCES})
  ucon_configure_target(${name})
  target_compile_features(${name} PUBLIC cxx_std_17)
  target_link_libraries(${name} PUBLIC ${A_PUBLIC_DEPS} PRIVATE ${A_PRIVATE_DEPS})
endfunction()

# ucon_executable(name SOURCES ... DEPS ...): output name is the target name (build/bin/<name>).
function(ucon_executable name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  ucon_configure_target(${name})
  target_link_libraries(${name} PRIVATE ${A_DEPS})
endfunction()

# ucon_gtest(name SOURCES ... DEPS ... [LABELS ...]): a GoogleTest binary registered with ctest.
function(ucon_gtest name)
  cmake_parse_arguments(A "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  ucon_configure_target(${name})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  target_link_libraries(${name} PRIVATE ${A_DEPS} GTest::gtest GTest::gtest_main)
  if(NOT A_TIMEOUT)
    set(A_TIMEOUT 120)
  endif()
  # Multi-process tests measure rates and losses over real sockets: run them alone, so a
  # parallel unit test cannot starve them into a false failure.
  set(serial FALSE)
  if("integration" IN_LIST A_LABELS)
    set(serial TRUE)
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
    PROPERTIES LABELS "${A_LABELS}" TIMEOUT ${A_TIMEOUT} RUN_SERIAL ${serial}
    DISCOVERY_TIMEOUT 30)
endfunction()
