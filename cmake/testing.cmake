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

# Which tests start first. make starts catkin's run_tests targets in the order they were declared, one type
# after the other (gtests, then rostests, then the others); four at a time, a long test declared late
# ended the run alone for minutes. A group made here, before any test, is visited first: catkin creates its
# run_tests_<package> targets only when they do not exist yet, and does the same as below when it does.
if(CATKIN_ENABLE_TESTING)
  add_custom_target(run_tests_${PROJECT_NAME})
  add_custom_target(_run_tests_${PROJECT_NAME})
  add_dependencies(run_tests _run_tests_${PROJECT_NAME})
  foreach(prefix run_tests _run_tests)
    add_custom_target(${prefix}_${PROJECT_NAME}_first)
    add_dependencies(${prefix}_${PROJECT_NAME} ${prefix}_${PROJECT_NAME}_first)
  endforeach()
endif()

# scl_tests_first(TEST...): these tests start first, in this order; each named as in catkin's targets,
# TYPE_NAME (gtest_test_core, rostest_test_ros_team.test, tools_demo_city). Called once every test exists.
# (make visits a target's prerequisites in the order the prerequisites were created, so each test gets a
# target of its own here, made in the order given.)
function(scl_tests_first)
  if(NOT CATKIN_ENABLE_TESTING)
    return()
  endif()
  set(index 0)
  foreach(test IN LISTS ARGN)
    foreach(prefix run_tests _run_tests)
      if(NOT TARGET ${prefix}_${PROJECT_NAME}_${test})
        message(FATAL_ERROR "scl_tests_first: no test ${test} (target ${prefix}_${PROJECT_NAME}_${test})")
      endif()
      add_custom_target(${prefix}_${PROJECT_NAME}_first_${index})
      add_dependencies(${prefix}_${PROJECT_NAME}_first_${index} ${prefix}_${PROJECT_NAME}_${test})
      add_dependencies(${prefix}_${PROJECT_NAME}_first ${prefix}_${PROJECT_NAME}_first_${index})
    endforeach()
    math(EXPR index "${index} + 1")
  endforeach()
endfunction()
