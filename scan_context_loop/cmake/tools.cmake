# Command-line tools (SCL_BUILD_TOOLS): the evaluator, the benchmark and the real-pair demo, all with the
# argument parser of scan_context_common/cli.h (the simulator's tool is in scan_context_sim).
add_executable(scan_context_evaluate tools/evaluate_main.cpp)
target_link_libraries(scan_context_evaluate scan_context_loop_eval ${scan_context_common_LIBRARIES})

add_executable(scan_context_pairs tools/pairs_demo.cpp)
target_link_libraries(scan_context_pairs scan_context_loop_eval ${scan_context_common_LIBRARIES})
add_executable(scan_context_bench tools/bench.cpp)
target_link_libraries(scan_context_bench scan_context_loop_eval ${scan_context_common_LIBRARIES} ${PCL_FILTERS_LIBRARIES})
add_executable(scan_context_bench_database tools/bench_database.cpp)
target_link_libraries(scan_context_bench_database scan_context_loop_core ${scan_context_common_LIBRARIES})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_cli test/test_main.cpp test/tools/test_cli.cpp)
  target_link_libraries(test_cli ${scan_context_common_LIBRARIES})
endif()
