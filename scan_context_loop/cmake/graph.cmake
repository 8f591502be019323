# The reference pose-graph backend (Ceres) and the trajectory error: ROS-free, in their own library so
# that the detector's core does not depend on Ceres.
find_package(Ceres REQUIRED)
add_library(scan_context_loop_graph src/graph/pose_graph.cpp src/graph/trajectory_error.cpp src/graph/keyframe_map.cpp)
target_include_directories(scan_context_loop_graph PUBLIC include ${EIGEN3_INCLUDE_DIRS} ${PCL_INCLUDE_DIRS})
target_link_libraries(scan_context_loop_graph PUBLIC Ceres::ceres ${PCL_FILTERS_LIBRARIES} ${PCL_COMMON_LIBRARIES})

install(TARGETS scan_context_loop_graph
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_graph test/test_main.cpp test/graph/test_pose_graph.cpp test/graph/test_trajectory_error.cpp
    test/graph/test_keyframe_map.cpp)
  target_link_libraries(test_graph scan_context_loop_graph)
endif()
