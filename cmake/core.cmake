# ROS-free core: Eigen, PCL, FLANN and the standard library only.
add_library(scan_context_loop_core
  src/core/config.cpp
  src/core/keyframes.cpp
  src/core/settings.cpp
  src/core/descriptor.cpp
  src/core/alignment.cpp
  src/core/database.cpp
  src/core/detector.cpp
  src/core/odometry_trust.cpp
  src/core/world_tilt.cpp
  src/core/registration.cpp
  src/core/principal_axes.cpp
  src/core/coarse_search.cpp
  src/core/free_space.cpp
  src/core/pcl_refinement.cpp
  src/core/verification.cpp
  src/core/acceptance_rule.cpp
  src/core/cloud_store.cpp
  src/core/consistency.cpp
  src/core/loop_tracking.cpp
  src/core/gravity_alignment.cpp
  src/core/crc32.cpp
  src/core/file_io.cpp
  src/core/block_arena.cpp
  src/core/database_file.cpp
  src/core/database_writer.cpp
  src/core/pose_corrections.cpp
  src/core/team_matcher.cpp
  src/core/team_consistency.cpp
  src/core/task_thread.cpp
)
# PCL's registration templates make these three the slowest sources to compile: each alone, so that a change
# to one compiles it and not a batch around it (cmake/unity.cmake).
scl_unity_alone(src/core/registration.cpp src/core/pcl_refinement.cpp src/core/verification.cpp)
target_include_directories(scan_context_loop_core PUBLIC
  include ${EIGEN3_INCLUDE_DIRS} ${PCL_INCLUDE_DIRS} ${FLANN_INCLUDE_DIRS})
# FLANN's C++ index is header-only; it needs lz4 for its serialisation code. The database writer's thread
# needs the threads library (a separate libpthread before glibc 2.34, as on Ubuntu 20.04).
find_package(Threads REQUIRED)
target_link_libraries(scan_context_loop_core PUBLIC ${PCL_COMMON_LIBRARIES} ${PCL_FILTERS_LIBRARIES}
  ${PCL_KDTREE_LIBRARIES} ${PCL_SEARCH_LIBRARIES} ${PCL_REGISTRATION_LIBRARIES} lz4 Threads::Threads)
target_compile_definitions(scan_context_loop_core PUBLIC ${PCL_DEFINITIONS})
# Lets the compiler vectorise the binning loop (if-conversion of float selects, sqrt without errno);
# the core neither reads errno nor traps on floating-point exceptions. NaN/Inf handling is unchanged.
target_compile_options(scan_context_loop_core PRIVATE -fno-math-errno -fno-trapping-math)

install(TARGETS scan_context_loop_core
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # A small simulated drive around a block (test/common/sim_drive.h), compiled once for the core's, the
  # evaluator's and the nodes' tests.
  add_library(scan_context_loop_sim_drive STATIC test/common/sim_drive.cpp)
  target_link_libraries(scan_context_loop_sim_drive PUBLIC scan_context_sim)

  scl_test(test_core SOURCES
      test/test_main.cpp
      test/core/test_descriptor.cpp
      test/core/test_alignment.cpp
      test/core/test_database.cpp
      test/core/test_database_index.cpp
      test/core/test_bad_input.cpp
      test/core/test_real_data.cpp
      test/core/test_scenes.cpp
      test/core/test_verification.cpp
      test/core/test_acceptance_rule.cpp
      test/core/test_cloud_store.cpp
      test/core/test_free_space.cpp
      test/core/test_consistency.cpp
      test/core/test_loop_tracking.cpp
      test/core/test_viewpoints.cpp
      test/core/test_gravity_alignment.cpp
      test/core/test_keyframes.cpp
      test/core/test_reconfigure.cpp
      test/core/test_sessions.cpp
      test/core/test_relocalization.cpp
      test/core/test_kitti_io.cpp
      test/core/test_simulated_places.cpp
      test/core/test_hard_revisits.cpp
      test/core/test_odometry_trust.cpp
      test/core/test_database_file.cpp
      test/core/test_pose_corrections.cpp
      test/core/test_file_io.cpp
      test/core/test_block_arena.cpp
      test/core/test_chunked_log.cpp
      test/core/test_team_matcher.cpp
      test/core/test_task_thread.cpp
      test/core/test_team_consistency.cpp
      test/core/test_principal_axes.cpp
      test/common/file_faults.cpp
    # The real-data tests read KITTI scans (eval/kitti_io.h); the simulated-data tests cast scans with the
    # simulator. file_faults.cpp's link, fsync, ... take precedence over the C library's for the core
    # library's calls (test/common/file_faults.h); they find the real ones with dlsym.
    LIBS scan_context_loop_eval scan_context_sim scan_context_loop_sim_drive ${PCL_IO_LIBRARIES} ${CMAKE_DL_LIBS}
    DEFINES SCL_SHARED_DATA="${SCL_SHARED_DATA}"
    INCLUDES src/core)  # principal_axes.h, a private header

  # Saving off the detector's thread: small and quick, so that ThreadSanitizer runs it too
  # (scripts/dev/sanitize).
  scl_test(test_database_writer
    SOURCES test/test_main.cpp test/core/test_database_writer.cpp test/core/test_scenes.cpp
    LIBS scan_context_loop_eval DEFINES SCL_SHARED_DATA="${SCL_SHARED_DATA}")

  # The same faults preloaded into a node's process (LD_PRELOAD), chosen by the file SCL_FILE_FAULTS names.
  add_library(scl_file_faults SHARED test/common/file_faults.cpp)
  target_link_libraries(scl_file_faults ${CMAKE_DL_LIBS})

endif()
