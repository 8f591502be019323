# The reference pose-graph backend (Ceres) and its keyframe map: ROS-free, in a library of its own that
# only the backend's nodelet and the evaluator's trajectory correction link, built when Ceres is found
# (scl_find_backend in settings.cmake). graph/ceres_compat.h bridges the Ceres versions.
if(NOT SCL_WITH_BACKEND)
  return()
endif()
add_library(scan_context_loop_graph src/graph/pose_graph.cpp src/graph/keyframe_map.cpp src/graph/pose_graph_settings.cpp
  src/graph/map_files.cpp src/graph/map_set.cpp)
target_include_directories(scan_context_loop_graph PUBLIC include ${EIGEN3_INCLUDE_DIRS} ${PCL_INCLUDE_DIRS})
# Ceres 1.14 exports no Ceres::ceres target: its CMake package names its library in CERES_LIBRARIES.
target_include_directories(scan_context_loop_graph PRIVATE ${CERES_INCLUDE_DIRS})
# The core's settings tables (core/settings.h) hold the node's keys too (graph/pose_graph_settings.h).
target_link_libraries(scan_context_loop_graph PUBLIC scan_context_loop_core ${PCL_FILTERS_LIBRARIES}
  ${PCL_COMMON_LIBRARIES} PRIVATE ${CERES_LIBRARIES})

install(TARGETS scan_context_loop_graph
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # The map files are read back with PCL's own PCD reader; the factor's Jacobians are checked against
  # Ceres's automatic ones through the library's private header. file_faults.cpp stands in for rename()
  # and renameat2() (a save killed part-way), reaching libc's through dlsym.
  scl_test(test_graph
    SOURCES test/test_main.cpp test/graph/test_pose_graph.cpp test/graph/test_pose_graph_chains.cpp
      test/graph/test_keyframe_map.cpp test/graph/test_map_files.cpp test/common/file_faults.cpp
      test/graph/test_relative_pose_cost.cpp test/graph/test_graph_study.cpp test/graph/test_graph_weights.cpp
    INCLUDES src/graph ${CERES_INCLUDE_DIRS}
    LIBS scan_context_loop_graph scan_context_loop_eval scan_context_sim ${PCL_IO_LIBRARIES} ${CERES_LIBRARIES} ${CMAKE_DL_LIBS}
    DEFINES SCL_SHARED_DATA="${SCL_SHARED_DATA}")
endif()
