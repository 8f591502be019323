# The ROS adapter (a library the two nodelets share, with no plugin in it), the loop-closure nodelet (the
# plugin library, its classes alone: the loop-closure nodelet and the base station's) and their standalone nodes.
add_library(scan_context_loop_ros
  src/ros/shared/parameters.cpp
  src/ros/shared/frame_ids.cpp
  src/ros/shared/cloud_input.cpp
  src/ros/loop_closure/markers.cpp
  src/ros/loop_closure/live_settings.cpp
  src/ros/loop_closure/loop_pair.cpp
  src/ros/shared/pose_input.cpp
  src/ros/loop_closure/sensor_extrinsic.cpp
  src/ros/shared/exception_barrier.cpp
  src/ros/loop_closure/heap_statistics.cpp
  src/ros/shared/stored_keyframe.cpp
  src/ros/loop_closure/corrected_poses.cpp
  src/ros/team/team_exchange.cpp
  src/ros/team/team_worker.cpp
  src/ros/team/team_requests.cpp
  src/ros/team/service_deadline.cpp
  src/ros/loop_closure/keyframe_queue.cpp
  src/ros/loop_closure/keyframe_input.cpp
  src/ros/loop_closure/keyframe_source.cpp
  src/ros/loop_closure/keyframe_processor.cpp
  src/ros/loop_closure/keyframe_timing.cpp
  src/ros/loop_closure/node_output.cpp
  src/ros/loop_closure/keyframe_worker.cpp
  src/ros/loop_closure/loop_publisher.cpp
  src/ros/loop_closure/keyframe_publisher.cpp
  src/ros/loop_closure/marker_publisher.cpp
  src/ros/loop_closure/node_diagnostics.cpp
  src/ros/shared/database_paths.cpp
  src/ros/shared/data_clock.cpp
  src/ros/loop_closure/database_services.cpp
  src/ros/loop_closure/database_saving.cpp
  src/ros/loop_closure/loop_closure_ros.cpp
  src/ros/team/team_base_ros.cpp
)
# The adapters' headers are private (src/ros, included as "shared/...", "loop_closure/...", "team/...",
# "pose_graph/..."): the nodelets, the nodes and the tests see them, nothing installs them.
target_include_directories(scan_context_loop_ros PUBLIC include src/ros ${catkin_INCLUDE_DIRS})
target_link_libraries(scan_context_loop_ros PUBLIC scan_context_loop_core ${catkin_LIBRARIES}
  ${PCL_FILTERS_LIBRARIES} ${PCL_COMMON_LIBRARIES})
add_dependencies(scan_context_loop_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)

add_library(scan_context_loop_nodelet src/ros/loop_closure/loop_closure_nodelet.cpp src/ros/team/team_base_nodelet.cpp)
target_link_libraries(scan_context_loop_nodelet scan_context_loop_ros)

add_executable(loop_closure_node src/ros/loop_closure/loop_closure_node.cpp)
target_include_directories(loop_closure_node PRIVATE include src/ros ${catkin_INCLUDE_DIRS})
target_link_libraries(loop_closure_node ${catkin_LIBRARIES})

# The base station: one process, one loop-closure adapter per robot of a team.
add_executable(team_base_node src/ros/team/team_base_node.cpp)
target_include_directories(team_base_node PRIVATE include src/ros ${catkin_INCLUDE_DIRS})
target_link_libraries(team_base_node ${catkin_LIBRARIES})

install(TARGETS scan_context_loop_ros scan_context_loop_nodelet loop_closure_node team_base_node
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(FILES nodelets.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
