# The command-line programs, one folder each under tools/, and their argument parser, a library of its
# own (tools/cli/) that only the programs link. The simulator (tools/simulate/, on the library of
# sim/) is always built here: the rostests simulate their bags with it. With SCL_BUILD_TOOLS: the
# evaluator (installed, `rosrun scan_context_loop scan_context_evaluate`), the benchmarks and the
# real-pair demo.
add_library(scan_context_loop_cli STATIC tools/cli/cli.cpp)
target_include_directories(scan_context_loop_cli PUBLIC tools/cli)

find_package(rosbag REQUIRED)
find_package(tf2_msgs REQUIRED)
add_executable(scan_context_simulate tools/simulate/simulate_main.cpp tools/simulate/sim_bag.cpp
  tools/simulate/simulate_team.cpp)
target_include_directories(scan_context_simulate PRIVATE ${catkin_INCLUDE_DIRS} ${rosbag_INCLUDE_DIRS}
  ${tf2_msgs_INCLUDE_DIRS})
target_link_libraries(scan_context_simulate scan_context_sim scan_context_loop_cli ${catkin_LIBRARIES}
  ${rosbag_LIBRARIES})

if(SCL_BUILD_TOOLS)
  add_executable(scan_context_evaluate tools/evaluate/evaluate_main.cpp tools/evaluate/evaluate_team.cpp)
  target_link_libraries(scan_context_evaluate scan_context_loop_eval scan_context_loop_cli)
  install(TARGETS scan_context_evaluate RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

  add_executable(scan_context_pairs tools/pairs/pairs_demo.cpp)
  target_link_libraries(scan_context_pairs scan_context_loop_eval scan_context_loop_cli)
  add_executable(scan_context_bench tools/bench/bench.cpp)
  target_link_libraries(scan_context_bench scan_context_loop_eval scan_context_loop_cli ${PCL_FILTERS_LIBRARIES})
  add_executable(scan_context_bench_database tools/bench/bench_database.cpp)
  target_link_libraries(scan_context_bench_database scan_context_loop_eval scan_context_loop_cli)
  add_executable(scan_context_bench_team tools/bench/bench_team.cpp)
  target_link_libraries(scan_context_bench_team scan_context_loop_eval scan_context_loop_cli)
endif()

# The files written from the settings tables of both nodes (the pose_graph node's come with the backend):
# doc/parameters.md, config/default.yaml, config/pose_graph.yaml and cfg/LoopClosure.cfg. They are
# committed; the tool (installed, `rosrun scan_context_loop scan_context_parameters`) prints or rewrites
# them, test_parameter_files compares them with the files in the source tree.
if(SCL_WITH_BACKEND)
  add_library(scan_context_loop_parameter_files STATIC tools/parameters/setting_row.cpp
    tools/parameters/parameters_page.cpp tools/parameters/defaults_yaml.cpp tools/parameters/reconfigure_cfg.cpp
    tools/parameters/generated_files.cpp)
  target_include_directories(scan_context_loop_parameter_files PUBLIC tools/parameters)
  target_link_libraries(scan_context_loop_parameter_files PUBLIC scan_context_loop_graph)
  if(SCL_BUILD_TOOLS)
    add_executable(scan_context_parameters tools/parameters/parameters_main.cpp)
    target_link_libraries(scan_context_parameters scan_context_loop_parameter_files scan_context_loop_cli)
    install(TARGETS scan_context_parameters RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
  endif()
  if(CATKIN_ENABLE_TESTING)
    scl_test(test_parameter_files SOURCES test/test_main.cpp test/tools/test_parameter_files.cpp
      test/tools/test_readme_settings.cpp
      LIBS scan_context_loop_parameter_files DEFINES SCL_PACKAGE_DIR="${SCL_PACKAGE_DIR}")
  endif()
endif()

if(CATKIN_ENABLE_TESTING)
  scl_test(test_cli SOURCES test/test_main.cpp test/tools/test_cli.cpp LIBS scan_context_loop_cli)
endif()
