# KITTI-format evaluator: a ROS-free library (KITTI I/O, metrics, ground truth, trajectory error, YAML
# config); its tool is in tools.cmake. The trajectory correction needs the pose-graph backend.
find_package(yaml-cpp REQUIRED)
add_library(scan_context_loop_eval src/eval/kitti_io.cpp src/eval/metrics.cpp src/eval/relocalization.cpp
  src/eval/config_file.cpp src/eval/sequence.cpp src/eval/prior_map.cpp src/eval/evaluation.cpp
  src/eval/trajectory_error.cpp src/eval/trajectory_correction_files.cpp src/eval/sequence_scorer.cpp
  src/eval/team_sequence.cpp src/eval/team_session.cpp src/eval/team_evaluation.cpp src/eval/team_map_files.cpp)
target_include_directories(scan_context_loop_eval PUBLIC include ${YAML_CPP_INCLUDE_DIR})
target_link_libraries(scan_context_loop_eval PUBLIC scan_context_loop_core yaml-cpp)
if(SCL_WITH_BACKEND)
  target_sources(scan_context_loop_eval PRIVATE src/eval/trajectory_correction.cpp src/eval/trajectory_correction_map.cpp
    src/eval/correction_graph.cpp src/eval/graph_study.cpp src/eval/team_map.cpp)
  target_link_libraries(scan_context_loop_eval PUBLIC scan_context_loop_graph)
else()
  target_sources(scan_context_loop_eval PRIVATE src/eval/trajectory_correction_unavailable.cpp src/eval/team_map_unavailable.cpp)
endif()

install(TARGETS scan_context_loop_eval
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # Simulated drives written as KITTI-format sequences, for the evaluator's tests.
  add_library(scan_context_loop_eval_sequences STATIC test/common/written_sequence.cpp)
  target_include_directories(scan_context_loop_eval_sequences PRIVATE ${GTEST_INCLUDE_DIRS})
  target_link_libraries(scan_context_loop_eval_sequences scan_context_loop_eval scan_context_loop_sim_drive)

  scl_test(test_eval_metrics SOURCES test/test_main.cpp test/eval/test_metrics.cpp test/eval/test_trajectory_error.cpp
    LIBS scan_context_loop_eval)
  # A prior map given as a saved database: its own binary, a few seconds.
  scl_test(test_eval_database_prior SOURCES test/test_main.cpp test/eval/test_database_prior.cpp
    LIBS scan_context_loop_eval_sequences)
  # A tiny team of two robots scored offline (--team); the map part with the backend only.
  scl_test(test_eval_team SOURCES test/test_main.cpp test/eval/test_team_evaluation.cpp
    LIBS scan_context_loop_eval_sequences)
  if(SCL_WITH_BACKEND)
    # Whole evaluations of simulated drives, with the trajectory correction.
    scl_test(test_eval SOURCES test/test_main.cpp test/eval/test_evaluation.cpp test/eval/test_relocalization.cpp
      LIBS scan_context_loop_eval_sequences
      DEFINES SCL_SHARED_DATA="${SCL_SHARED_DATA}" SCL_PACKAGE_DIR="${SCL_PACKAGE_DIR}")
  endif()
endif()
