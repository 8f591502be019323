# Street LiDAR simulator: a ROS-free library (writes sequences with eval/kitti_io.h); its tool, which also
# writes rosbags, is in tools.cmake.
add_library(scan_context_loop_sim
  src/sim/world.cpp
  src/sim/placement.cpp
  src/sim/street_kit.cpp
  src/sim/street_generator.cpp
  src/sim/world_changes.cpp
  src/sim/traffic.cpp
  src/sim/sensor.cpp
  src/sim/trajectory.cpp
  src/sim/platform_tilt.cpp
  src/sim/polyline.cpp
  src/sim/city_drive.cpp
  src/sim/narrow_drive.cpp
  src/sim/sequence_writer.cpp
)
target_include_directories(scan_context_loop_sim PUBLIC include ${EIGEN3_INCLUDE_DIRS} ${PCL_INCLUDE_DIRS})
target_link_libraries(scan_context_loop_sim PUBLIC scan_context_loop_eval ${PCL_COMMON_LIBRARIES} ${PCL_FILTERS_LIBRARIES} pthread)


if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_sim test/test_main.cpp test/sim/test_world.cpp test/sim/test_sensor.cpp
    test/sim/test_trajectory.cpp test/sim/test_sequence.cpp test/sim/test_drives.cpp
    test/sim/test_changed_world.cpp test/sim/test_hard_revisits.cpp test/sim/test_narrow.cpp)
  target_link_libraries(test_sim scan_context_loop_sim scan_context_loop_core)
  target_compile_definitions(test_sim PRIVATE SCL_SHARED_DATA="${SCL_SHARED_DATA}")
endif()
