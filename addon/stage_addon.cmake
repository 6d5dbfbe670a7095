# cmake -DSRC=<addon/radiosity> -DSTAGE=<dir> -DNATIVE=<module file>[|<module file>...] -P stage_addon.cmake
# Lays out STAGE/radiosity/ = Python sources + manifest + the native modules (one per Python).
foreach(var SRC STAGE NATIVE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "stage_addon.cmake: -D${var}=... missing")
  endif()
endforeach()
file(REMOVE_RECURSE ${STAGE})
file(MAKE_DIRECTORY ${STAGE}/radiosity)
file(COPY ${SRC}/ DESTINATION ${STAGE}/radiosity
     FILES_MATCHING PATTERN "*.py" PATTERN "*.toml"
     PATTERN "__pycache__" EXCLUDE)
# A native module left in the source tree (developer convenience) must not shadow the build's.
file(GLOB stale ${STAGE}/radiosity/radiosity_native*.so ${STAGE}/radiosity/radiosity_native.py)
if(stale)
  file(REMOVE ${stale})
endif()
string(REPLACE "|" ";" NATIVE "${NATIVE}")
file(COPY ${NATIVE} DESTINATION ${STAGE}/radiosity)
