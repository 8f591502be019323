# The build settings the repository's packages share (installed with scan_context_common and included by
# find_package(scan_context_common)): call scl_compile_settings() right after project().
macro(scl_compile_settings)
  if(NOT CMAKE_BUILD_TYPE)
    set(CMAKE_BUILD_TYPE Release)
  endif()
  set(CMAKE_CXX_STANDARD 17)
  set(CMAKE_CXX_STANDARD_REQUIRED ON)
  add_compile_options(-Wall -Wextra)
endmacro()

# For a package's tests: SCL_PACKAGE_DIR (the package's folder, links resolved), SCL_REPO_ROOT (the
# repository, one level up) and SCL_SHARED_DATA (the real data beside the repository, read in place).
macro(scl_repository_paths)
  get_filename_component(SCL_PACKAGE_XML "${CMAKE_CURRENT_SOURCE_DIR}/package.xml" REALPATH)
  get_filename_component(SCL_PACKAGE_DIR "${SCL_PACKAGE_XML}" DIRECTORY)
  get_filename_component(SCL_REPO_ROOT "${SCL_PACKAGE_DIR}" DIRECTORY)
  set(SCL_SHARED_DATA "${SCL_REPO_ROOT}/../shared/data")
endmacro()
