# The build settings of the whole package; scl_compile_settings() runs right after project().
#
# C++17, and Eigen's class-specific aligned operator new everywhere (EIGEN_HAS_CXX17_OVERALIGN=0): the
# platforms' PCL (ros.org's on Ubuntu 20.04, Debian's, ROS-O's) is built as C++14, where Eigen gives every
# PointCloud and point type a class operator new/delete. With C++17's default, Eigen 3.4 leaves those
# operators out of our code, so a cloud our code allocates and PCL's code frees would pair two different
# allocators. Eigen 3.3 always defines the class operators (it knows no C++17 over-alignment), so the
# setting is the one both Eigen versions then share.
macro(scl_compile_settings)
  if(NOT CMAKE_BUILD_TYPE)
    set(CMAKE_BUILD_TYPE Release)
  endif()
  set(CMAKE_CXX_STANDARD 17)
  set(CMAKE_CXX_STANDARD_REQUIRED ON)
  set(CMAKE_CXX_EXTENSIONS OFF)
  add_compile_options(-Wall -Wextra)
  add_definitions(-DEIGEN_HAS_CXX17_OVERALIGN=0)
  # A program or library is not linked again when only a shared library it links was rebuilt: it loads
  # that library at run time. A change to one core source then relinks the core library alone, not every
  # test and tool. (What generates data at build time opts out: CMakeLists.txt.)
  set(CMAKE_LINK_DEPENDS_NO_SHARED ON)
endmacro()

# Ceres for the reference pose-graph backend: any of 1.14 (Ubuntu 20.04), 2.0 (22.04), 2.1 (Debian 12)
# and 2.2 (24.04). Sets SCL_WITH_BACKEND; without Ceres the backend is skipped and everything else built.
macro(scl_find_backend)
  option(SCL_BUILD_BACKEND "build the reference pose-graph backend when Ceres is found" ON)
  set(SCL_WITH_BACKEND OFF)
  if(SCL_BUILD_BACKEND)
    find_package(Ceres QUIET)
  endif()
  if(SCL_BUILD_BACKEND AND Ceres_FOUND)
    set(SCL_WITH_BACKEND ON)
    message(STATUS "scan_context_loop: the pose-graph backend is built with Ceres ${Ceres_VERSION}")
  elseif(SCL_BUILD_BACKEND)
    message(WARNING "scan_context_loop: Ceres was not found, so the reference pose-graph backend "
      "(pose_graph nodelet and node, the evaluator's trajectory correction and their tests) is not built. "
      "The loop-closure nodelet does not need it. Install Ceres (rosdep key libceres-dev) to build it.")
  else()
    message(STATUS "scan_context_loop: the pose-graph backend is off (SCL_BUILD_BACKEND=OFF)")
  endif()
endmacro()

# For the tests: SCL_PACKAGE_DIR (the package's folder, links resolved, which is the repository's root)
# and SCL_SHARED_DATA (the real data beside the repository, read in place).
macro(scl_repository_paths)
  get_filename_component(SCL_PACKAGE_XML "${CMAKE_CURRENT_SOURCE_DIR}/package.xml" REALPATH)
  get_filename_component(SCL_PACKAGE_DIR "${SCL_PACKAGE_XML}" DIRECTORY)
  # Without "..": the clones of the repository side by side then compile the same path into the tests, so
  # a fresh clone's test objects come from ccache too (a define is part of ccache's key).
  get_filename_component(SCL_SHARED_DATA "${SCL_PACKAGE_DIR}/../shared/data" ABSOLUTE)
endmacro()
