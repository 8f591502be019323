# The ROS adapter (a library the two nodelets share, with no plugin in it), the loop-closure nodelet (the
# plugin library, its classes alone: the loop-closure nodelet and the base station's) and their standalone nodes.
add_library(scan_context_loop_ros
  src/ros/parameters.cpp
  src/ros/frame_ids.cpp
  src/ros/cloud_input.cpp
  src/ros/markers.cpp
  src/ros/live_settings.cpp
  src/ros/loop_pair.cpp
  src/ros/pose_input.cpp
  src/ros/sensor_extrinsic.cpp
  src/ros/exception_barrier.cpp
  src/ros/heap_statistics.cpp
  src/ros/stored_keyframe.cpp
  src/ros/corrected_poses.cpp
  src/ros/team_exchange.cpp
  src/ros/team_worker.cpp
  src/ros/service_deadline.cpp
  src/ros/keyframe_queue.cpp
  src/ros/keyframe_input.cpp
  src/ros/keyframe_processor.cpp
  src/ros/keyframe_worker.cpp
  src/ros/loop_publisher.cpp
  src/ros/keyframe_publisher.cpp
  src/ros/marker_publisher.cpp
  src/ros/node_diagnostics.cpp
  src/ros/database_paths.cpp
  src/ros/database_services.cpp
  src/ros/loop_closure_ros.cpp
  src/ros/team_base_ros.cpp
)
target_include_directories(scan_context_loop_ros PUBLIC include ${catkin_INCLUDE_DIRS})
target_link_libraries(scan_context_loop_ros PUBLIC scan_context_loop_core ${catkin_LIBRARIES}
  ${PCL_FILTERS_LIBRARIES} ${PCL_COMMON_LIBRARIES})
add_dependencies(scan_context_loop_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)

add_library(scan_context_loop_nodelet src/ros/loop_closure_nodelet.cpp src/ros/team_base_nodelet.cpp)
target_link_libraries(scan_context_loop_nodelet scan_context_loop_ros)

add_executable(loop_closure_node src/ros/loop_closure_node.cpp)
target_include_directories(loop_closure_node PRIVATE include ${catkin_INCLUDE_DIRS})
target_link_libraries(loop_closure_node ${catkin_LIBRARIES})

# The base station: one process, one loop-closure adapter per robot of a team.
add_executable(team_base_node src/ros/team_base_node.cpp)
target_include_directories(team_base_node PRIVATE include ${catkin_INCLUDE_DIRS})
target_link_libraries(team_base_node ${catkin_LIBRARIES})

install(TARGETS scan_context_loop_ros scan_context_loop_nodelet loop_closure_node team_base_node
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(FILES nodelets.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  find_package(roslaunch REQUIRED)
  add_library(scan_context_loop_ros_harness STATIC test/ros/harness.cpp test/ros/child_process.cpp)
  target_include_directories(scan_context_loop_ros_harness PUBLIC include ${catkin_INCLUDE_DIRS} ${GTEST_INCLUDE_DIRS})
  target_link_libraries(scan_context_loop_ros_harness scan_context_loop_core scan_context_loop_sim_drive
    ${catkin_LIBRARIES})
  add_dependencies(scan_context_loop_ros_harness ${PROJECT_NAME}_generate_messages_cpp)

  add_rostest_gtest(test_ros_loops test/ros/nodelet_loops.test test/ros/test_loops.cpp)
  target_link_libraries(test_ros_loops scan_context_loop_ros_harness)
  add_rostest(test/ros/node_lio.test DEPENDENCIES test_ros_loops loop_closure_node scan_context_loop_nodelet)
  add_rostest(test/ros/verified_loops.test DEPENDENCIES test_ros_loops scan_context_loop_nodelet)
  add_rostest(test/ros/consistent_loops.test DEPENDENCIES test_ros_loops scan_context_loop_nodelet)
  add_dependencies(test_ros_loops scan_context_loop_nodelet)
  add_rostest_gtest(test_ros_bad_input test/ros/bad_input.test test/ros/test_bad_input.cpp)
  target_link_libraries(test_ros_bad_input scan_context_loop_ros_harness scan_context_loop_ros)
  add_dependencies(test_ros_bad_input scan_context_loop_nodelet)

  roslaunch_add_file_check(launch)
endif()

if(CATKIN_ENABLE_TESTING)
  add_rostest_gtest(test_ros_tf_world test/ros/tf_world.test test/ros/test_tf_world.cpp)
  target_link_libraries(test_ros_tf_world scan_context_loop_ros_harness)
  add_dependencies(test_ros_tf_world scan_context_loop_nodelet loop_closure_node)
endif()

if(CATKIN_ENABLE_TESTING)
  add_rostest_gtest(test_ros_parameters test/ros/parameters.test test/ros/test_parameters.cpp)
  target_link_libraries(test_ros_parameters scan_context_loop_ros ${catkin_LIBRARIES})
endif()

if(CATKIN_ENABLE_TESTING)
  add_rostest_gtest(test_ros_same_loops test/ros/same_loops.test test/ros/test_same_loops.cpp)
  target_link_libraries(test_ros_same_loops scan_context_loop_ros_harness scan_context_loop_ros scan_context_loop_eval)
  add_dependencies(test_ros_same_loops loop_closure_node scan_context_loop_nodelet)
endif()

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_ros_markers test/test_main.cpp test/ros/test_markers.cpp)
  target_link_libraries(test_ros_markers scan_context_loop_ros)
  catkin_add_gtest(test_ros_database_paths test/test_main.cpp test/ros/test_database_paths.cpp)
  target_link_libraries(test_ros_database_paths scan_context_loop_ros)
  catkin_add_gtest(test_ros_team_base test/test_main.cpp test/ros/test_team_base.cpp)
  target_link_libraries(test_ros_team_base scan_context_loop_ros)
endif()

if(CATKIN_ENABLE_TESTING)
  # One rostest per stack's launch file: test/ros/stack_bag.test plays a short bag shaped like that
  # stack's output, which the simulator (sim/) writes here when the tests are built (the KITTI folder it reads
  # the scans back from is removed once the bag is written).
  set(bags ${PROJECT_BINARY_DIR}/stack_bags)
  add_executable(test_ros_stacks EXCLUDE_FROM_ALL test/ros/test_stacks.cpp)
  target_link_libraries(test_ros_stacks scan_context_loop_ros_harness ${GTEST_LIBRARIES})
  add_dependencies(tests test_ros_stacks)
  # A single pass also runs the reference backend where it is built; without it (no Ceres) the tests check
  # the loops alone (stack_bag.test's `backend`).
  set(stack_test_deps test_ros_stacks loop_closure_node scan_context_loop_nodelet)
  if(SCL_WITH_BACKEND)
    set(backend true)
    list(APPEND stack_test_deps pose_graph_node scan_context_loop_pose_graph_nodelet)
  else()
    set(backend false)
  endif()
  foreach(stack aloam lego_loam lio_sam fast_lio)
    add_custom_command(OUTPUT ${bags}/${stack}.bag
      COMMAND scan_context_simulate ${bags}/${stack} --block --stack ${stack} --sensor vlp16 --voxel 0.2 --threads 2
        --mount-pitch 6
        --bag ${bags}/${stack}.bag
      COMMAND ${CMAKE_COMMAND} -E remove_directory ${bags}/${stack}/velodyne
      DEPENDS scan_context_simulate
      COMMENT "Simulating a bag shaped like ${stack}'s output"
      VERBATIM)
    add_custom_target(scan_context_loop_${stack}_bag DEPENDS ${bags}/${stack}.bag)
    add_dependencies(tests scan_context_loop_${stack}_bag)
    file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/test/ros/${stack}.test CONTENT
"<launch>
  <include file=\"$(find scan_context_loop)/test/ros/stack_bag.test\">
    <arg name=\"stack\" value=\"${stack}\"/>
    <arg name=\"bag\" value=\"${bags}/${stack}.bag\"/>
    <arg name=\"backend\" value=\"${backend}\"/>
  </include>
</launch>
")
    add_rostest(${PROJECT_BINARY_DIR}/test/ros/${stack}.test
      DEPENDENCIES scan_context_loop_${stack}_bag ${stack_test_deps})
  endforeach()
  # Several robots: a simulated team's bag (three robots, the third a minute late) and the rostest that runs
  # their nodes on it (test/ros/team.test).
  add_custom_command(OUTPUT ${bags}/team/team.bag
    COMMAND scan_context_simulate ${bags}/team --team 3 --team-start 0,0,60 --sensor vlp16 --voxel 0.2 --threads 2
      --bag ${bags}/team/team.bag
    COMMAND ${CMAKE_COMMAND} -E remove_directory ${bags}/team/robot1/velodyne
    COMMAND ${CMAKE_COMMAND} -E remove_directory ${bags}/team/robot2/velodyne
    COMMAND ${CMAKE_COMMAND} -E remove_directory ${bags}/team/robot3/velodyne
    DEPENDS scan_context_simulate
    COMMENT "Simulating a team of three robots"
    VERBATIM)
  add_custom_target(scan_context_loop_team_bag DEPENDS ${bags}/team/team.bag)
  add_dependencies(tests scan_context_loop_team_bag)
  add_executable(test_ros_team EXCLUDE_FROM_ALL test/ros/test_team.cpp)
  target_link_libraries(test_ros_team scan_context_loop_ros_harness scan_context_sim ${GTEST_LIBRARIES})
  add_dependencies(tests test_ros_team)
  file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/test/ros/team.test CONTENT
"<launch>
  <include file=\"$(find scan_context_loop)/test/ros/team.test\">
    <arg name=\"bag\" value=\"${bags}/team/team.bag\"/>
    <arg name=\"team_file\" value=\"${bags}/team/team.txt\"/>
    <arg name=\"backend\" value=\"${backend}\"/>
  </include>
</launch>
")
  set(team_test_deps scan_context_loop_team_bag test_ros_team loop_closure_node scan_context_loop_nodelet)
  if(SCL_WITH_BACKEND)
    list(APPEND team_test_deps pose_graph_node scan_context_loop_pose_graph_nodelet)
  endif()
  add_rostest(${PROJECT_BINARY_DIR}/test/ros/team.test DEPENDENCIES ${team_test_deps})
  # The same team with a base station: one node, a detector per robot.
  file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/test/ros/team_base.test CONTENT
"<launch>
  <include file=\"$(find scan_context_loop)/test/ros/team_base.test\">
    <arg name=\"bag\" value=\"${bags}/team/team.bag\"/>
    <arg name=\"team_file\" value=\"${bags}/team/team.txt\"/>
  </include>
</launch>
")
  add_rostest(${PROJECT_BINARY_DIR}/test/ros/team_base.test
    DEPENDENCIES scan_context_loop_team_bag test_ros_team team_base_node scan_context_loop_nodelet)

  add_executable(test_ros_team_input EXCLUDE_FROM_ALL test/ros/test_team_input.cpp)
  target_link_libraries(test_ros_team_input scan_context_loop_ros_harness ${GTEST_LIBRARIES})
  add_dependencies(tests test_ros_team_input)
  add_rostest(test/ros/team_input.test DEPENDENCIES test_ros_team_input loop_closure_node scan_context_loop_nodelet)
  # A hostile peer: a flood of records, services that never answer, a bad node name, a claim to another
  # robot's id; an unload in the middle of a hung request.
  add_executable(test_ros_team_hostile EXCLUDE_FROM_ALL test/ros/test_team_hostile.cpp)
  target_link_libraries(test_ros_team_hostile scan_context_loop_ros_harness ${GTEST_LIBRARIES})
  add_dependencies(tests test_ros_team_hostile)
  add_rostest(test/ros/team_hostile.test
    DEPENDENCIES test_ros_team_hostile loop_closure_node scan_context_loop_nodelet)

  # One bag played again and again (rosbag play -l): each pass a session that closes loops into the first.
  file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/test/ros/fast_lio_replayed.test CONTENT
"<launch>
  <include file=\"$(find scan_context_loop)/test/ros/stack_bag.test\">
    <arg name=\"stack\" value=\"fast_lio\"/>
    <arg name=\"bag\" value=\"${bags}/fast_lio.bag\"/>
    <arg name=\"replay\" value=\"true\"/>
  </include>
</launch>
")
  add_rostest(${PROJECT_BINARY_DIR}/test/ros/fast_lio_replayed.test
    DEPENDENCIES test_ros_stacks scan_context_loop_fast_lio_bag loop_closure_node scan_context_loop_nodelet)
endif()

if(CATKIN_ENABLE_TESTING)
  # The dynamic_reconfigure description, the standard-type loops, cloud and pose input, frame ids, the
  # sensor extrinsic, the worker's exception barrier and heap statistics, and the stamps the database
  # keeps: no ROS master needed.
  catkin_add_gtest(test_ros_units test/ros/test_live_settings.cpp test/ros/test_pose_input.cpp
    test/ros/test_cloud_input.cpp test/ros/test_frame_ids.cpp test/ros/test_sensor_extrinsic.cpp
    test/ros/test_exception_barrier.cpp test/ros/test_heap_statistics.cpp test/ros/test_stored_keyframe.cpp
    test/ros/test_keyframe_worker.cpp test/ros/test_corrected_poses.cpp)
  target_link_libraries(test_ros_units scan_context_loop_ros ${catkin_LIBRARIES})
endif()

if(CATKIN_ENABLE_TESTING)
  add_rostest_gtest(test_ros_reconfigure test/ros/reconfigure.test test/ros/test_reconfigure.cpp)
  target_link_libraries(test_ros_reconfigure scan_context_loop_ros_harness)
  add_dependencies(test_ros_reconfigure scan_context_loop_nodelet)
endif()

if(CATKIN_ENABLE_TESTING)
  add_rostest_gtest(test_ros_sessions test/ros/sessions.test test/ros/test_sessions.cpp)
  target_link_libraries(test_ros_sessions scan_context_loop_ros_harness)
  add_dependencies(test_ros_sessions scan_context_loop_nodelet)
endif()

if(CATKIN_ENABLE_TESTING)
  add_rostest_gtest(test_ros_relocalization test/ros/relocalization.test test/ros/test_relocalization.cpp)
  target_link_libraries(test_ros_relocalization scan_context_loop_ros_harness)
  # A standalone node with the file-fault library preloaded (test/common/file_faults.h) fails its autosaves.
  add_dependencies(test_ros_relocalization scan_context_loop_nodelet loop_closure_node scl_file_faults)
  target_compile_definitions(test_ros_relocalization PRIVATE SCL_FILE_FAULTS_LIBRARY="$<TARGET_FILE:scl_file_faults>")
endif()

if(CATKIN_ENABLE_TESTING)
  # The fuzz targets' kept inputs (test/fuzz_regressions/), replayed through the targets' own code built
  # without libFuzzer; the odometry check and the in-memory database parser. No ROS master needed.
  catkin_add_gtest(test_fuzz_inputs test/test_main.cpp test/fuzz/test_fuzz_inputs.cpp test/fuzz/fuzz_input.cpp
    test/fuzz/fuzz_cloud.cpp test/fuzz/fuzz_odometry.cpp test/fuzz/fuzz_database.cpp)
  target_link_libraries(test_fuzz_inputs scan_context_loop_ros ${catkin_LIBRARIES})
  target_compile_definitions(test_fuzz_inputs PRIVATE SCL_PACKAGE_DIR="${SCL_PACKAGE_DIR}")
endif()

if(CATKIN_ENABLE_TESTING)
  # Unloading the nodelet and SIGINT to a node or manager while a burst keeps the queue full.
  add_rostest_gtest(test_ros_shutdown test/ros/shutdown.test test/ros/test_shutdown.cpp)
  target_link_libraries(test_ros_shutdown scan_context_loop_ros_harness)
  add_dependencies(test_ros_shutdown scan_context_loop_nodelet loop_closure_node)
endif()

if(CATKIN_ENABLE_TESTING)
  # Frame ids written tf1's way in, tf2's names out; the extrinsic repeated on /tf; silent inputs named.
  add_rostest_gtest(test_ros_frames test/ros/frames.test test/ros/test_frames.cpp)
  target_link_libraries(test_ros_frames scan_context_loop_ros_harness)
  add_dependencies(test_ros_frames loop_closure_node scan_context_loop_nodelet)
endif()
