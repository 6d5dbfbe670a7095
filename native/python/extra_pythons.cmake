# The same radiosity_native module built for more Pythons than the one the build runs with.
#
# A compiled module loads only in the CPython minor version it was built for, and each Blender
# embeds one: 3.11 in Debian's Blender 3.4 and the official 4.1-5.0, 3.13 from 5.1 on. One zip
# serves them all by carrying one module per version side by side; each file has its
# interpreter's extension suffix (radiosity_native.cpython-313-x86_64-linux-gnu.so), so
# Python's own import picks the matching one and skips the others.
#
# RADIOSITY_EXTRA_PYTHONS: interpreters (a ;-list of paths) to build the module for besides
# Python_EXECUTABLE. "auto" (the default) looks for each version in RADIOSITY_BLENDER_PYTHONS
# that Python_EXECUTABLE is not (scripts/find_python.sh) and warns about each it cannot find.
# Only the interpreter's headers and extension suffix are used: pybind11 is header-only and
# the same for every version, and a module links no libpython.
set(RADIOSITY_BLENDER_PYTHONS "3.11;3.13" CACHE STRING
    "CPython versions of the Blenders the add-on zip serves (used by RADIOSITY_EXTRA_PYTHONS=auto)")
set(RADIOSITY_EXTRA_PYTHONS "auto" CACHE STRING
    "Interpreters to build radiosity_native for besides Python_EXECUTABLE: ;-list of paths, auto, or empty")

# Sets <out>_VERSION, <out>_SUFFIX, <out>_INCLUDE from asking the interpreter itself.
function(_radiosity_python_config exe out)
  execute_process(
    COMMAND ${exe} -c "import sys, sysconfig; print('%d.%d' % sys.version_info[:2]); print(sysconfig.get_config_var('EXT_SUFFIX')); print(sysconfig.get_paths()['include'])"
    OUTPUT_VARIABLE text RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT rc EQUAL 0)
    set(${out}_VERSION "" PARENT_SCOPE)
    return()
  endif()
  string(REPLACE "\n" ";" lines "${text}")
  list(GET lines 0 version)
  list(GET lines 1 suffix)
  list(GET lines 2 include)
  set(${out}_VERSION ${version} PARENT_SCOPE)
  set(${out}_SUFFIX ${suffix} PARENT_SCOPE)
  set(${out}_INCLUDE ${include} PARENT_SCOPE)
endfunction()

# The interpreters to build for, and for "auto" a warning for each Blender Python not found.
set(_radiosity_primary "${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}")
set(_radiosity_extra ${RADIOSITY_EXTRA_PYTHONS})
set(_radiosity_explicit TRUE)
if(RADIOSITY_EXTRA_PYTHONS STREQUAL "auto")
  set(_radiosity_extra "")
  set(_radiosity_explicit FALSE)
  foreach(version IN LISTS RADIOSITY_BLENDER_PYTHONS)
    if(version VERSION_EQUAL _radiosity_primary)
      continue()
    endif()
    string(REPLACE "." "" tag "${version}")
    execute_process(COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/find_python.sh ${version}
                    OUTPUT_VARIABLE exe RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(rc EQUAL 0)
      list(APPEND _radiosity_extra ${exe})
    else()
      set(blenders "the Blenders that embed Python ${version}")
      if(version VERSION_EQUAL 3.13)
        set(blenders "Blender 5.1 and later (Python 3.13)")
      elseif(version VERSION_EQUAL 3.11)
        set(blenders "Debian's Blender 3.4 and Blender 4.1-5.0 (Python 3.11)")
      endif()
      message(WARNING "radiosity: no CPython ${version} found (PATH, pyenv, $PYTHON${tag}): "
                      "the add-on zip will not load in ${blenders}. "
                      "Install one with its headers (scripts/install_deps.sh says how) or pass "
                      "-DRADIOSITY_EXTRA_PYTHONS=/path/to/python${version}.")
    endif()
  endforeach()
endif()

set(RADIOSITY_NATIVE_TARGETS radiosity_native)   # every module the add-on zip carries
foreach(exe IN LISTS _radiosity_extra)
  _radiosity_python_config(${exe} cfg)
  set(problem "")
  if(cfg_VERSION STREQUAL "")
    set(problem "it does not run")
  elseif(cfg_VERSION VERSION_EQUAL _radiosity_primary)
    set(problem "Python_EXECUTABLE is already ${cfg_VERSION}")
  elseif(NOT EXISTS "${cfg_INCLUDE}/Python.h")
    set(problem "it has no headers (no ${cfg_INCLUDE}/Python.h)")
  elseif(cfg_VERSION VERSION_GREATER_EQUAL 3.13 AND pybind11_VERSION VERSION_LESS 2.13)
    set(problem "pybind11 ${pybind11_VERSION} predates Python 3.13 (pip install 'pybind11>=2.13')")
  endif()
  if(problem)
    # Asked for by name: stop. Found by "auto": build the rest and say what is missing.
    if(_radiosity_explicit)
      message(FATAL_ERROR "radiosity: cannot build radiosity_native for ${exe}: ${problem}")
    endif()
    message(WARNING "radiosity: no radiosity_native for ${exe}: ${problem}")
    continue()
  endif()
  string(REPLACE "." "" tag "${cfg_VERSION}")
  set(target radiosity_native_cp${tag})
  # What pybind11_add_module does for the main module, with this interpreter's headers and
  # suffix instead of the build's Python.
  add_library(${target} MODULE python/module.cpp)
  target_include_directories(${target} SYSTEM PRIVATE ${cfg_INCLUDE})
  target_link_libraries(${target} PRIVATE radiosity_core pybind11::headers)
  if(NOT DEFINED CMAKE_INTERPROCEDURAL_OPTIMIZATION)
    target_link_libraries(${target} PRIVATE pybind11::lto)
  endif()
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME radiosity_native PREFIX "" SUFFIX "${cfg_SUFFIX}"
    CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  string(TOUPPER "${CMAKE_BUILD_TYPE}" build_type)
  if(NOT build_type MATCHES "DEBUG|RELWITHDEBINFO|NONE")
    pybind11_strip(${target})
  endif()
  list(APPEND RADIOSITY_NATIVE_TARGETS ${target})
  message(STATUS "radiosity: radiosity_native also for Python ${cfg_VERSION} (${exe}): ${cfg_SUFFIX}")
endforeach()
# For addon/ (a sibling directory): the modules to stage into the zip.
set_property(GLOBAL PROPERTY RADIOSITY_NATIVE_TARGETS ${RADIOSITY_NATIVE_TARGETS})
