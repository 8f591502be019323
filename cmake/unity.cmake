# Batched compilation (a "unity build"): each target's C++ sources are compiled SCL_UNITY_BATCH at a time,
# as one translation unit that includes them in the target's order. The headers they share (PCL, Eigen,
# ROS, gtest) are then read and their templates instantiated once a batch instead of once a file, which
# takes about a third off a full build of the package and its tests.
#
# CMake's own UNITY_BUILD writes the sources' absolute paths into its batch files, so the batch a fresh
# clone compiles differs from the one another clone compiled, and ccache (whose key holds the file's text)
# could not reuse the objects. The batches here include each source by its path relative to the batch,
# which is the same in every clone and in catkin_tools' layout (build/<package>/ beside src/<package>/).
#
# A source is compiled with the ones before it in its batch: a name at file scope (in an anonymous
# namespace too) must not be defined twice within a target. SCL_UNITY_BUILD=OFF compiles each file alone.
#
# A change to one source compiles its whole batch again, so the few sources that take a minute or more on
# their own (PCL's registration templates) are compiled alone: scl_unity_alone(file...) marks them, before
# scl_unity_batches runs in the same directory. Batched with seven others, a change to one of them took
# 2.5 minutes to compile instead of 1.
option(SCL_UNITY_BUILD "compile each target's sources in batches (fewer, larger translation units)" ON)
set(SCL_UNITY_BATCH 8 CACHE STRING "sources per batch of the batched compilation")

# scl_unity_batches(DIRECTORY): batches the sources of every library and program defined in DIRECTORY.
function(scl_unity_batches directory)
  if(NOT SCL_UNITY_BUILD)
    return()
  endif()
  get_property(targets DIRECTORY "${directory}" PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(NOT type MATCHES "^(EXECUTABLE|STATIC_LIBRARY|SHARED_LIBRARY|MODULE_LIBRARY)$")
      continue()
    endif()
    get_target_property(sources ${target} SOURCES)
    get_target_property(source_dir ${target} SOURCE_DIR)
    set(cpp)
    set(others)
    foreach(source IN LISTS sources)
      if(source MATCHES "^\\$<")
        list(APPEND others "${source}")
        continue()
      endif()
      get_filename_component(absolute "${source}" ABSOLUTE BASE_DIR "${source_dir}")
      get_source_file_property(alone "${absolute}" SCL_UNITY_ALONE)
      if(source MATCHES "\\.cpp$" AND NOT alone)
        list(APPEND cpp "${absolute}")
      else()
        list(APPEND others "${source}")
      endif()
    endforeach()
    list(LENGTH cpp count)
    if(count LESS 2)
      continue()
    endif()
    set(batch_dir "${PROJECT_BINARY_DIR}/scl_unity/${target}")
    set(batches)
    set(text "")
    set(in_batch 0)
    set(index 0)
    foreach(source IN LISTS cpp)
      file(RELATIVE_PATH relative "${batch_dir}" "${source}")
      string(APPEND text "#include \"${relative}\"\n")
      math(EXPR in_batch "${in_batch} + 1")
      if(in_batch EQUAL SCL_UNITY_BATCH)
        _scl_unity_write("${batch_dir}" ${index} "${text}" batches)
        math(EXPR index "${index} + 1")
        set(text "")
        set(in_batch 0)
      endif()
    endforeach()
    if(in_batch GREATER 0)
      _scl_unity_write("${batch_dir}" ${index} "${text}" batches)
    endif()
    set_property(TARGET ${target} PROPERTY SOURCES ${others} ${batches})
  endforeach()
endfunction()

# scl_unity_alone(FILE...): these sources (relative to the current source directory) are compiled alone.
function(scl_unity_alone)
  set_source_files_properties(${ARGN} PROPERTIES SCL_UNITY_ALONE ON)
endfunction()

# Writes batch INDEX (only when its text changed, so that an unchanged batch is not compiled again) and
# appends its path to the list named OUT.
function(_scl_unity_write batch_dir index text out)
  set(file "${batch_dir}/batch_${index}.cpp")
  file(WRITE "${file}.new" "// The sources of one batch of the batched compilation (cmake/unity.cmake).\n${text}")
  configure_file("${file}.new" "${file}" COPYONLY)
  file(REMOVE "${file}.new")
  set(${out} ${${out}} "${file}" PARENT_SCOPE)
endfunction()
