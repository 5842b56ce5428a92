# Target helpers in the style of COLMAP_ADD_*: every module is one library with warnings on.

function(mocap_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(MOCAP_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Pixel loops in the image codecs and label passes: GCC's -O2 vectorises only loops that need no
# remainder handling ("very cheap" cost model), which leaves row loops of any image width scalar.
function(mocap_vectorize target)
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fvect-cost-model=dynamic>)
endfunction()

if(MOCAP_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  # A Debug sanitizer build at -Og with line tables (-g1 after CMake's -g wins): reports still name
  # function, file and line. At -O0 with full -g the instrumented Eigen loops made the sanitizer run most
  # of CI's time. -Og compiles in about two thirds of -O1's time (AddressSanitizer's advice) and its tests
  # run about a fifth slower, a far smaller cost (docs/architecture.md "Build").
  add_compile_options($<$<CONFIG:Debug>:-Og> $<$<CONFIG:Debug>:-g1>)
  add_link_options(-fsanitize=address,undefined)
endif()

# mocap_add_library(NAME name SRCS ... DEPS ... [PRIVATE_DEPS ...])
# Headers are included as "<module>/<file>.h" relative to src/ (or the top level for capture/, exporters/).
function(mocap_add_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${ARG_NAME} STATIC ${ARG_SRCS})
  target_include_directories(${ARG_NAME} PUBLIC ${CMAKE_SOURCE_DIR}/src ${CMAKE_SOURCE_DIR})
  target_link_libraries(${ARG_NAME} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  set_target_properties(${ARG_NAME} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  mocap_set_warnings(${ARG_NAME})
endfunction()

# mocap_add_test(NAME module_what SRCS ... DEPS ... LABELS ... [PROPERTIES name value ...])
# Registers each GoogleTest case with ctest as "module/Suite.Case" with the given labels (joined) and
# test properties (single values, e.g. FIXTURES_REQUIRED and ENVIRONMENT for tests/slurm's cluster).
function(mocap_add_test)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS;LABELS;PROPERTIES" ${ARGN})
  string(JOIN "-" label ${ARG_LABELS})
  # The sanitizer run leaves out the e2e, slow and slurm tests (Makefile `test-asan`), so a sanitizer
  # build does not build them by default nor register their cases: the target exists (callers add
  # dependencies and definitions to it) but is built only when asked for.
  if(MOCAP_SANITIZE AND label MATCHES "(^|-)(e2e|slow|slurm)(-|$)")
    add_executable(${ARG_NAME} EXCLUDE_FROM_ALL ${ARG_SRCS})
    target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gmock GTest::gtest_main)
    return()
  endif()
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gmock GTest::gtest_main)
  target_compile_definitions(${ARG_NAME} PRIVATE
    MOCAP_SHARED_DIR="${MOCAP_SHARED_DIR}" MOCAP_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
    MOCAP_BINARY_DIR="${CMAKE_BINARY_DIR}")
  # The test harness's own translation units carry AddressSanitizer only, unoptimised: UBSan's checks
  # cost about a quarter of each file's compile time and -O1 about 40 % more than -O0, while the code
  # under test (every library and the mocaplabel binary) keeps both sanitizers at -Og, where the tests
  # spend their time (docs/architecture.md "Build").
  if(MOCAP_SANITIZE)
    target_compile_options(${ARG_NAME} PRIVATE -fno-sanitize=undefined -O0)
  else()
    # The release build's test files at -Og: a third less compile time than -O2, and the work they
    # test runs in the libraries, which keep -O2.
    target_compile_options(${ARG_NAME} PRIVATE $<$<CONFIG:RelWithDebInfo>:-Og>)
  endif()
  mocap_set_warnings(${ARG_NAME})
  # One label joined with '-' ("sim-egl-e2e"): gtest_discover_tests passes a list property on as its
  # first element only, and ctest's -L / -LE take regular expressions, so `-L sim` and `-LE e2e` both
  # match the joined label.
  gtest_discover_tests(${ARG_NAME} TEST_PREFIX "${ARG_NAME}/" PROPERTIES LABELS "${label}" ${ARG_PROPERTIES}
                       DISCOVERY_TIMEOUT 60)
endfunction()

function(mocap_add_executable)
  cmake_parse_arguments(ARG "" "NAME;OUTPUT_NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS})
  if(ARG_OUTPUT_NAME)
    set_target_properties(${ARG_NAME} PROPERTIES OUTPUT_NAME ${ARG_OUTPUT_NAME})
  endif()
  mocap_set_warnings(${ARG_NAME})
endfunction()

function(mocap_add_benchmark)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  target_compile_definitions(${ARG_NAME} PRIVATE MOCAP_SHARED_DIR="${MOCAP_SHARED_DIR}")
  mocap_set_warnings(${ARG_NAME})
endfunction()
