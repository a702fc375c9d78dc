# cmake -DSTAGE=.. -DADDON_SRC=.. -DSHADERS_SRC=.. -DLIBRARY=.. -DZIP=.. -P make_zip.cmake
file(REMOVE_RECURSE "${STAGE}")
set(_dir "${STAGE}/rendezvous")
file(COPY "${ADDON_SRC}/" DESTINATION "${_dir}"
     PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE PATTERN ".gitignore" EXCLUDE
     PATTERN "install.cmake" EXCLUDE PATTERN "make_zip.cmake" EXCLUDE)
file(COPY "${SHADERS_SRC}" DESTINATION "${_dir}"
     PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE PATTERN ".gitignore" EXCLUDE)
file(COPY "${LIBRARY}" DESTINATION "${_dir}")
file(REMOVE "${ZIP}")
execute_process(COMMAND "${CMAKE_COMMAND}" -E tar cf "${ZIP}" --format=zip rendezvous
                WORKING_DIRECTORY "${STAGE}" RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "zip failed: ${_rc}")
endif()
message(STATUS "Wrote ${ZIP}")
