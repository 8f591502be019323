# Command-line tools (SCL_BUILD_TOOLS): the evaluator, the simulator, the benchmark and the real-pair demo,
# all with one argument parser (tools/cli.h).
add_library(scan_context_loop_cli STATIC tools/cli.cpp)
target_include_directories(scan_context_loop_cli PUBLIC tools)

add_executable(scan_context_evaluate tools/evaluate_main.cpp)
target_link_libraries(scan_context_evaluate scan_context_loop_eval scan_context_loop_cli)

add_executable(scan_context_simulate tools/simulate_main.cpp tools/sim_bag.cpp)
target_include_directories(scan_context_simulate PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(scan_context_simulate scan_context_loop_sim scan_context_loop_cli ${catkin_LIBRARIES})

add_executable(scan_context_pairs tools/pairs_demo.cpp)
target_link_libraries(scan_context_pairs scan_context_loop_eval scan_context_loop_cli)
add_executable(scan_context_bench tools/bench.cpp)
target_link_libraries(scan_context_bench scan_context_loop_eval scan_context_loop_cli ${PCL_FILTERS_LIBRARIES})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_cli test/test_main.cpp test/tools/test_cli.cpp)
  target_link_libraries(test_cli scan_context_loop_cli)
endif()
