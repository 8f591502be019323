# KITTI-format evaluator: a ROS-free library (metrics, ground truth, YAML config; KITTI I/O from
# scan_context_common); its tool is in tools.cmake.
find_package(yaml-cpp REQUIRED)
add_library(scan_context_loop_eval src/eval/metrics.cpp src/eval/relocalization.cpp src/eval/config_file.cpp
  src/eval/evaluation.cpp)
target_include_directories(scan_context_loop_eval PUBLIC include ${YAML_CPP_INCLUDE_DIR})
target_link_libraries(scan_context_loop_eval PUBLIC scan_context_loop_core ${scan_context_common_LIBRARIES} yaml-cpp)

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_eval test/test_main.cpp test/eval/test_metrics.cpp test/eval/test_evaluation.cpp
    test/eval/test_relocalization.cpp test/common/sim_drive.cpp)
  target_link_libraries(test_eval scan_context_loop_eval ${scan_context_sim_LIBRARIES})
  target_compile_definitions(test_eval PRIVATE SCL_SHARED_DATA="${SCL_SHARED_DATA}" SCL_PACKAGE_DIR="${SCL_PACKAGE_DIR}")
endif()
