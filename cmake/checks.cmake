# Checks of the package as a whole (with the tests): package.xml against rosdep's index and Noetic's
# package list, read offline from the compat folder beside the repository (SCL_COMPAT); the launch files;
# the documentation's links; the install space.
if(NOT CATKIN_ENABLE_TESTING)
  return()
endif()
set(SCL_COMPAT "${SCL_PACKAGE_DIR}/../shared/compat" CACHE PATH "rosdep's index and the older libraries' sources")
if(EXISTS "${SCL_COMPAT}/rosdep/base.yaml")
  catkin_run_tests_target(package package_xml package_xml.xml
    COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/package/check_package_xml.py --rosdep ${SCL_COMPAT}/rosdep --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/package_xml.xml")
else()
  message(STATUS "scan_context_loop: no rosdep index in ${SCL_COMPAT}/rosdep, so the package.xml check is not run")
endif()

# The launch files a user starts, loaded with roslaunch's own loader (nothing is started) with defaults and
# with every argument changed: names, namespaces, topics, manager, RViz, sim time, the stacks' settings.
catkin_run_tests_target(launch files launch_files.xml
  COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/launch/check_launch_files.py --package ${PROJECT_SOURCE_DIR} --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/launch_files.xml")

# What the scripts install on Debian's ROS (apt) and on a ros.org Noetic (rosdep from package.xml, apt only
# outside ROS), printed by a dry run.
catkin_run_tests_target(package install_commands install_commands.xml
  COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/package/check_install_commands.py --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/install_commands.xml")

# Every relative link and anchor of README.md and doc/*.md resolves.
catkin_run_tests_target(package doc_links doc_links.xml
  COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/package/check_doc_links.py --package ${PROJECT_SOURCE_DIR} --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/doc_links.xml")

# scripts/measure/peers.py, which measures other programs beside this package for the results page.
catkin_run_tests_target(tools peer_measurement peer_measurement.xml
  COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/tools/check_peer_measurement.py --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/peer_measurement.xml")

# The install space as a user gets it (scripts/dev/test installs first and turns this on): the package found
# there, its launch files' nodes up with their topics, the evaluator through rosrun.
option(SCL_TEST_INSTALL_SPACE "run_tests also checks the install space (install it first)" OFF)
if(SCL_TEST_INSTALL_SPACE)
  set(scl_backend_flag "")
  if(SCL_WITH_BACKEND)
    set(scl_backend_flag "--backend")
  endif()
  catkin_run_tests_target(package install_space install_space.xml
    COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/install/check_install_space.py --install ${CMAKE_INSTALL_PREFIX} ${scl_backend_flag} --xunit ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/install_space.xml --logs ${PROJECT_BINARY_DIR}/install_space_logs")
endif()
