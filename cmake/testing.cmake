# One helper for every test target of the package:
#
#   scl_test(NAME
#     [ROSTEST launch.test]       a rostest (add_rostest_gtest); else a gtest run without a master
#     SOURCES file.cpp...         the test's sources
#     [LIBS target...]            what it links (a rostest links the harness too)
#     [NEEDS target...]           what must be built before it runs (nodelets, nodes, bags)
#     [DEFINES NAME=value...]     compile definitions
#     [INCLUDES dir...])          private include directories
#
#   scl_launch_test(launch.test NEEDS target...)
#     one more rostest of an existing test binary (its launch file names the binary), or a launch file
#     generated into the build folder.
include(CMakeParseArguments)

# The tests' own sources are compiled at -O1 (after the build type's -O3, so it wins): their code sets up
# and checks, the work they test is in the libraries, which keep the build type's flags. On this package's
# test sources -O1 takes about two thirds of -O3's compile time (and -O0 no less than -O1: it emits more).
set(SCL_TEST_COMPILE_OPTIONS -O1)

function(scl_test name)
  cmake_parse_arguments(T "" "ROSTEST" "SOURCES;LIBS;NEEDS;DEFINES;INCLUDES" ${ARGN})
  if(T_ROSTEST)
    add_rostest_gtest(${name} ${T_ROSTEST} ${T_SOURCES})
    target_link_libraries(${name} scan_context_loop_ros_harness ${T_LIBS})
  else()
    catkin_add_gtest(${name} ${T_SOURCES})
    target_link_libraries(${name} ${T_LIBS})
  endif()
  target_compile_options(${name} PRIVATE ${SCL_TEST_COMPILE_OPTIONS})
  if(T_NEEDS)
    add_dependencies(${name} ${T_NEEDS})
  endif()
  if(T_DEFINES)
    target_compile_definitions(${name} PRIVATE ${T_DEFINES})
  endif()
  if(T_INCLUDES)
    target_include_directories(${name} PRIVATE ${T_INCLUDES})
  endif()
endfunction()

function(scl_launch_test launch)
  cmake_parse_arguments(T "" "" "NEEDS" ${ARGN})
  add_rostest(${launch} DEPENDENCIES ${T_NEEDS})
endfunction()
