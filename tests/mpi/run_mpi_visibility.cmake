# ctest: visimp-mpi under mpiexec (1 and 3 processes, oversubscribed) writes the same bytes as
# one `visimp visibility` process, and a bad input fails every process with exit code 1.
#   cmake -DVISIMP=... -DVISIMP_MPI=... -DMPIEXEC=... -DMESH=... -DWORK_DIR=... -P run_mpi_visibility.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(common --cameras 66 --resolution 96 --threads 1)
execute_process(COMMAND "${VISIMP}" visibility "${MESH}" "${WORK_DIR}/one.ply" ${common} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "visimp visibility failed: ${rc}")
endif()
foreach(np 1 3)
  execute_process(COMMAND "${MPIEXEC}" -np ${np} --oversubscribe "${VISIMP_MPI}" visibility "${MESH}"
                          "${WORK_DIR}/mpi${np}.ply" ${common} --json
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mpiexec -np ${np} failed (${rc}):\n${out}\n${err}")
  endif()
  if(NOT out MATCHES "\"processes\": ${np}")
    message(FATAL_ERROR "the -np ${np} summary does not say ${np} processes:\n${out}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK_DIR}/one.ply" "${WORK_DIR}/mpi${np}.ply"
                  RESULT_VARIABLE same)
  if(NOT same EQUAL 0)
    message(FATAL_ERROR "mpiexec -np ${np}: the output differs from one process's")
  endif()
endforeach()
execute_process(COMMAND "${MPIEXEC}" -np 3 --oversubscribe "${VISIMP_MPI}" visibility "${WORK_DIR}/missing.ply"
                        "${WORK_DIR}/never.ply" ${common} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "missing.ply" OR EXISTS "${WORK_DIR}/never.ply")
  message(FATAL_ERROR "a missing input must fail naming it and write nothing (rc ${rc}):\n${err}")
endif()
