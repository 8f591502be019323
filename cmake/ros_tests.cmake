# The ROS adapter's tests: gtests of its pieces (no master) and rostests of the nodelets and nodes, each
# declared with scl_test (cmake/testing.cmake). The stack and team rostests play bags the simulator
# writes into the build folder when the tests are built.
if(NOT CATKIN_ENABLE_TESTING)
  return()
endif()
find_package(rostest REQUIRED)
find_package(roslaunch REQUIRED)
add_library(scan_context_loop_ros_harness STATIC test/ros/harness.cpp test/ros/child_process.cpp)
target_compile_options(scan_context_loop_ros_harness PRIVATE ${SCL_TEST_COMPILE_OPTIONS})
target_include_directories(scan_context_loop_ros_harness PUBLIC include src/ros ${catkin_INCLUDE_DIRS} ${GTEST_INCLUDE_DIRS})
target_link_libraries(scan_context_loop_ros_harness scan_context_loop_core scan_context_loop_sim_drive
  ${catkin_LIBRARIES})
add_dependencies(scan_context_loop_ros_harness ${PROJECT_NAME}_generate_messages_cpp)
roslaunch_add_file_check(launch)

# The pieces, without a master: the dynamic_reconfigure description, the standard-type loops, cloud and
# pose input, frame ids, the sensor extrinsic, the worker's exception barrier and heap statistics, the
# stamps the database keeps; the markers, the map directory, the base station's robots.
scl_test(test_ros_units LIBS scan_context_loop_ros ${catkin_LIBRARIES}
  SOURCES test/ros/test_live_settings.cpp test/ros/test_pose_input.cpp test/ros/test_cloud_input.cpp
    test/ros/test_frame_ids.cpp test/ros/test_sensor_extrinsic.cpp test/ros/test_exception_barrier.cpp
    test/ros/test_heap_statistics.cpp test/ros/test_stored_keyframe.cpp test/ros/test_keyframe_worker.cpp
    test/ros/test_corrected_poses.cpp test/ros/test_data_clock.cpp)
scl_test(test_ros_markers SOURCES test/test_main.cpp test/ros/test_markers.cpp LIBS scan_context_loop_ros)
scl_test(test_ros_database_paths SOURCES test/test_main.cpp test/ros/test_database_paths.cpp LIBS scan_context_loop_ros)
scl_test(test_ros_team_base SOURCES test/test_main.cpp test/ros/test_team_base.cpp LIBS scan_context_loop_ros)
# The fuzz targets' kept inputs (test/fuzz_regressions/), replayed through the targets' own code built
# without libFuzzer; the odometry check and the in-memory database parser.
scl_test(test_fuzz_inputs LIBS scan_context_loop_ros ${catkin_LIBRARIES} DEFINES SCL_PACKAGE_DIR="${SCL_PACKAGE_DIR}"
  SOURCES test/test_main.cpp test/fuzz/test_fuzz_inputs.cpp test/fuzz/fuzz_input.cpp test/fuzz/fuzz_cloud.cpp
    test/fuzz/fuzz_odometry.cpp test/fuzz/fuzz_database.cpp)

# The nodelet and the node on known input.
set(nodelet scan_context_loop_nodelet)
scl_test(test_ros_loops ROSTEST test/ros/nodelet_loops.test SOURCES test/ros/test_loops.cpp NEEDS ${nodelet})
scl_launch_test(test/ros/node_lio.test NEEDS test_ros_loops loop_closure_node ${nodelet})
scl_launch_test(test/ros/node_lio_unheard.test NEEDS test_ros_loops loop_closure_node ${nodelet})
scl_launch_test(test/ros/verified_loops.test NEEDS test_ros_loops ${nodelet})
scl_launch_test(test/ros/consistent_loops.test NEEDS test_ros_loops ${nodelet})
scl_test(test_ros_bad_input ROSTEST test/ros/bad_input.test SOURCES test/ros/test_bad_input.cpp
  LIBS scan_context_loop_ros NEEDS ${nodelet})
scl_test(test_ros_tf_world ROSTEST test/ros/tf_world.test SOURCES test/ros/test_tf_world.cpp
  NEEDS ${nodelet} loop_closure_node)
scl_test(test_ros_parameters ROSTEST test/ros/parameters.test SOURCES test/ros/test_parameters.cpp
  LIBS scan_context_loop_ros scan_context_loop_ros_harness ${catkin_LIBRARIES} NEEDS loop_closure_node ${nodelet})
scl_test(test_ros_same_loops ROSTEST test/ros/same_loops.test SOURCES test/ros/test_same_loops.cpp
  LIBS scan_context_loop_ros scan_context_loop_eval NEEDS loop_closure_node ${nodelet})
scl_test(test_ros_reconfigure ROSTEST test/ros/reconfigure.test SOURCES test/ros/test_reconfigure.cpp NEEDS ${nodelet})
scl_test(test_ros_sessions ROSTEST test/ros/sessions.test SOURCES test/ros/test_sessions.cpp NEEDS ${nodelet})
# A standalone node with the file-fault library preloaded (test/common/file_faults.h) fails its autosaves.
scl_test(test_ros_relocalization ROSTEST test/ros/relocalization.test SOURCES test/ros/test_relocalization.cpp
  NEEDS ${nodelet} loop_closure_node scl_file_faults
  DEFINES SCL_FILE_FAULTS_LIBRARY="$<TARGET_FILE:scl_file_faults>")
# Unloading the nodelet and SIGINT to a node or manager while a burst keeps the queue full.
scl_test(test_ros_shutdown ROSTEST test/ros/shutdown.test SOURCES test/ros/test_shutdown.cpp
  NEEDS ${nodelet} loop_closure_node)
# Frame ids written tf1's way in, tf2's names out; the extrinsic repeated on /tf; silent inputs named.
scl_test(test_ros_frames ROSTEST test/ros/frames.test SOURCES test/ros/test_frames.cpp
  NEEDS loop_closure_node ${nodelet})

# One rostest per stack's launch file: test/ros/stack_bag.test plays a short bag shaped like that stack's
# output (the KITTI folder the simulator reads the scans back from is removed once the bag is written). A
# single pass also runs the reference backend where it is built; without it (no Ceres) the tests check
# the loops alone (stack_bag.test's `backend`).
set(bags ${PROJECT_BINARY_DIR}/stack_bags)
set(node_deps loop_closure_node ${nodelet})
if(SCL_WITH_BACKEND)
  set(backend true)
  list(APPEND node_deps pose_graph_node scan_context_loop_pose_graph_nodelet)
else()
  set(backend false)
endif()

# scl_bag(NAME OUTPUT ARGS...): the simulator writes OUTPUT when the tests are built (target scan_context_loop_NAME_bag).
function(scl_bag name output)
  set(removed)
  foreach(dir ${SCL_BAG_REMOVE})
    list(APPEND removed COMMAND ${CMAKE_COMMAND} -E remove_directory ${dir})
  endforeach()
  add_custom_command(OUTPUT ${output} COMMAND scan_context_simulate ${ARGN} --bag ${output} ${removed}
    DEPENDS scan_context_simulate COMMENT "Simulating ${name}" VERBATIM)
  add_custom_target(scan_context_loop_${name}_bag DEPENDS ${output})
  add_dependencies(tests scan_context_loop_${name}_bag)
endfunction()

# scl_bag_test(NAME LAUNCH ARGS...): a launch file in the build folder that includes test/ros/LAUNCH with ARGS
# (name value pairs), and its rostest.
function(scl_bag_test name launch)
  set(args "")
  set(list ${ARGN})
  while(list)
    list(POP_FRONT list arg value)
    string(APPEND args "    <arg name=\"${arg}\" value=\"${value}\"/>\n")
  endwhile()
  file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/test/ros/${name}.test CONTENT
"<launch>
  <include file=\"$(find scan_context_loop)/test/ros/${launch}\">
${args}  </include>
</launch>
")
endfunction()

# A test binary that rostests of generated launch files run (built with `tests`, not `all`).
function(scl_test_binary name)
  add_executable(${name} EXCLUDE_FROM_ALL ${ARGN})
  target_link_libraries(${name} scan_context_loop_ros_harness scan_context_sim ${GTEST_LIBRARIES})
  add_dependencies(tests ${name})
endfunction()

scl_test_binary(test_ros_stacks test/ros/test_stacks.cpp)
foreach(stack aloam lego_loam lio_sam fast_lio sc_aloam hdl_graph_slam)
  set(SCL_BAG_REMOVE ${bags}/${stack}/velodyne)
  scl_bag(${stack} ${bags}/${stack}.bag ${bags}/${stack} --block --stack ${stack} --sensor vlp16 --voxel 0.2
    --threads 2 --mount-pitch 6)
  scl_bag_test(${stack} stack_bag.test stack ${stack} bag ${bags}/${stack}.bag backend ${backend})
  scl_launch_test(${PROJECT_BINARY_DIR}/test/ros/${stack}.test
    NEEDS scan_context_loop_${stack}_bag test_ros_stacks ${node_deps})
endforeach()
# The demo in a tree without ../shared/data, scripts/demo --bag on each stack's bag (scripts/demo_bag, the
# part after the build), and a wrong --stack; all run the backend. One test a case, so that they run side
# by side (each has a master of its own).
if(SCL_WITH_BACKEND)
  foreach(case city wrong_stack aloam lego_loam lio_sam fast_lio sc_aloam hdl_graph_slam)
    catkin_run_tests_target(tools demo_${case} demo_${case}.xml
      COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/tools/check_demo.py --bags ${bags} --case ${case} --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/demo_${case}.xml")
  endforeach()
endif()
# SC-A-LOAM's sensor-frame clouds labelled with the world's frame, read as A-LOAM's: refused, with the fix.
scl_bag_test(stack_trap stack_trap.test bag ${bags}/sc_aloam.bag)
scl_launch_test(${PROJECT_BINARY_DIR}/test/ros/stack_trap.test
  NEEDS scan_context_loop_sc_aloam_bag test_ros_stacks ${node_deps})
# One bag played again and again (rosbag play -l): each pass a session that closes loops into the first.
scl_bag_test(fast_lio_replayed stack_bag.test stack fast_lio bag ${bags}/fast_lio.bag replay true)
scl_launch_test(${PROJECT_BINARY_DIR}/test/ros/fast_lio_replayed.test
  NEEDS test_ros_stacks scan_context_loop_fast_lio_bag loop_closure_node ${nodelet})

# Several robots: a simulated team's bag (three robots, the third 30 s late), their nodes on it
# (test/ros/team.test), and the same team with a base station: one node, a detector per robot.
set(SCL_BAG_REMOVE ${bags}/team/robot1/velodyne ${bags}/team/robot2/velodyne ${bags}/team/robot3/velodyne)
scl_bag(team ${bags}/team/team.bag ${bags}/team --team 3 --team-start 0,0,30 --sensor vlp16 --voxel 0.2 --threads 2)
scl_test_binary(test_ros_team test/ros/test_team.cpp)
scl_bag_test(team team.test bag ${bags}/team/team.bag team_file ${bags}/team/team.txt backend ${backend})
scl_launch_test(${PROJECT_BINARY_DIR}/test/ros/team.test NEEDS scan_context_loop_team_bag test_ros_team ${node_deps})
scl_bag_test(team_base team_base.test bag ${bags}/team/team.bag team_file ${bags}/team/team.txt)
scl_launch_test(${PROJECT_BINARY_DIR}/test/ros/team_base.test
  NEEDS scan_context_loop_team_bag test_ros_team team_base_node ${nodelet})
scl_test_binary(test_ros_team_input test/ros/test_team_input.cpp)
scl_launch_test(test/ros/team_input.test NEEDS test_ros_team_input loop_closure_node ${nodelet})
# A hostile peer: a flood of records, services that never answer, a bad node name, a claim to another
# robot's id; an unload in the middle of a hung request.
scl_test_binary(test_ros_team_hostile test/ros/test_team_hostile.cpp)
scl_launch_test(test/ros/team_hostile.test NEEDS test_ros_team_hostile loop_closure_node ${nodelet})
