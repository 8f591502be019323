# The reference pose-graph backend's nodelet (a plugin library of its own, beside the loop-closure
# nodelet's, in the same nodelets.xml) and its standalone node; built with the backend.
if(NOT SCL_WITH_BACKEND)
  return()
endif()
add_library(scan_context_loop_pose_graph_nodelet
  src/ros/pose_graph/pose_graph_parameters.cpp
  src/ros/pose_graph/pose_graph_ros.cpp
  src/ros/pose_graph/pose_graph_worker.cpp
  src/ros/pose_graph/pose_graph_output.cpp
  src/ros/pose_graph/pose_graph_saving.cpp
  src/ros/pose_graph/pose_graph_robots.cpp
  src/ros/pose_graph/pose_graph_nodelet.cpp)
target_link_libraries(scan_context_loop_pose_graph_nodelet scan_context_loop_ros scan_context_loop_graph)
add_executable(pose_graph_node src/ros/pose_graph/pose_graph_node.cpp)
target_include_directories(pose_graph_node PRIVATE include src/ros ${catkin_INCLUDE_DIRS})
target_link_libraries(pose_graph_node ${catkin_LIBRARIES})
install(TARGETS scan_context_loop_pose_graph_nodelet pose_graph_node
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  scl_test(test_ros_pose_graph ROSTEST test/ros/pose_graph.test SOURCES test/ros/test_pose_graph.cpp
    LIBS scan_context_loop_eval ${PCL_IO_LIBRARIES}
    NEEDS scan_context_loop_nodelet scan_context_loop_pose_graph_nodelet pose_graph_node)
  scl_test(test_ros_pose_graph_team ROSTEST test/ros/pose_graph_team.test SOURCES test/ros/test_pose_graph_team.cpp
    NEEDS pose_graph_node)
  scl_test(test_ros_corrected_relocalization ROSTEST test/ros/corrected_relocalization.test
    SOURCES test/ros/test_corrected_relocalization.cpp LIBS scan_context_sim
    NEEDS scan_context_loop_nodelet scan_context_loop_pose_graph_nodelet)
  # The backend's parameter reader runs in the parameter rostest (cmake/ros_tests.cmake).
  target_sources(test_ros_parameters PRIVATE test/ros/test_pose_graph_parameters.cpp)
  target_link_libraries(test_ros_parameters scan_context_loop_pose_graph_nodelet)
endif()
