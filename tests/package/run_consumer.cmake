# ctest: install this build into a fresh prefix, configure and build tests/package/consumer
# against it (nothing of the source or build tree on its paths), run both executables.
#   cmake -DBUILD_DIR=... -DWORK_DIR=... -DCONSUMER_DIR=... -DMESH=... -DCXX=... [-DFLAGS=...] -P run_consumer.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
foreach(f lib/cmake/visimp/visimpConfig.cmake lib/cmake/visimp/visimpConfigVersion.cmake
          include/visimp/simplify/simplify.h bin/visimp)
  if(NOT EXISTS "${WORK_DIR}/prefix/${f}")
    message(FATAL_ERROR "the install has no ${f}")
  endif()
endforeach()
run(${CMAKE_COMMAND} -S "${CONSUMER_DIR}" -B "${WORK_DIR}/build" -G Ninja -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" "-DCMAKE_CXX_FLAGS=${FLAGS}"
    "-DCMAKE_EXE_LINKER_FLAGS=${FLAGS}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer" "${MESH}")
message(STATUS "consumer: ${last_output}")
run("${WORK_DIR}/build/consumer_simplify_only")
# A version the package must refuse: 1.0 against 0.1.x.
file(WRITE "${WORK_DIR}/too_new/CMakeLists.txt"
     "cmake_minimum_required(VERSION 3.22)\nproject(too_new LANGUAGES CXX)\nfind_package(visimp 1.0 REQUIRED)\n")
execute_process(COMMAND ${CMAKE_COMMAND} -S "${WORK_DIR}/too_new" -B "${WORK_DIR}/too_new/build" -G Ninja
                "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(rc EQUAL 0)
  message(FATAL_ERROR "find_package(visimp 1.0) accepted version 0.1")
endif()
