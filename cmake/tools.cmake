# The tools' shared argument parser (tools/cli.h), which the simulator's tool uses too; with
# SCL_BUILD_TOOLS the command-line tools: the evaluator (installed, `rosrun scan_context_loop
# scan_context_evaluate`), the benchmarks and the real-pair demo.
add_library(scan_context_loop_cli STATIC tools/cli.cpp)
target_include_directories(scan_context_loop_cli PUBLIC tools)

if(SCL_BUILD_TOOLS)
  add_executable(scan_context_evaluate tools/evaluate_main.cpp)
  target_link_libraries(scan_context_evaluate scan_context_loop_eval scan_context_loop_cli)
  install(TARGETS scan_context_evaluate RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

  add_executable(scan_context_pairs tools/pairs_demo.cpp)
  target_link_libraries(scan_context_pairs scan_context_loop_eval scan_context_loop_cli)
  add_executable(scan_context_bench tools/bench.cpp)
  target_link_libraries(scan_context_bench scan_context_loop_eval scan_context_loop_cli ${PCL_FILTERS_LIBRARIES})
  add_executable(scan_context_bench_database tools/bench_database.cpp)
  target_link_libraries(scan_context_bench_database scan_context_loop_eval scan_context_loop_cli)
endif()

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_cli test/test_main.cpp test/tools/test_cli.cpp)
  target_link_libraries(test_cli scan_context_loop_cli)
endif()
