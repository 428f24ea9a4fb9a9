# The CTest test api_install: installs exao (component exao) into a fresh prefix, then
# configures, builds and runs tests/install/ against it, as a project outside exao would.
# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=... -P run.cmake
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run.cmake: -D${var}=... is required")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "ok: ${ARGN}")
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --component exao)

# What a consumer needs, and nothing of exao's internals.
file(GLOB_RECURSE installed RELATIVE ${prefix} ${prefix}/*)
list(SORT installed)
message(STATUS "installed: ${installed}")
foreach(required include/exao/exao.hpp include/exao/exao.h include/exao/export.h)
  if(NOT EXISTS ${prefix}/${required})
    message(FATAL_ERROR "not installed: ${required}")
  endif()
endforeach()
foreach(pattern "libexao\\.so" "cmake/exao/exao-config\\.cmake" "cmake/exao/exao-config-version\\.cmake"
                "cmake/exao/exao-targets\\.cmake" "pkgconfig/exao\\.pc")
  set(found ${installed})
  list(FILTER found INCLUDE REGEX "${pattern}")
  if(NOT found)
    message(FATAL_ERROR "not installed: ${pattern}")
  endif()
endforeach()
file(GLOB internal_headers ${prefix}/include/core ${prefix}/include/lut ${prefix}/include/bvh ${prefix}/include/glm)
if(internal_headers)
  message(FATAL_ERROR "internal headers installed: ${internal_headers}")
endif()

set(pc_dirs ${prefix}/lib/pkgconfig)
file(GLOB more_pc_dirs ${prefix}/lib/*/pkgconfig ${prefix}/lib64/pkgconfig)
list(APPEND pc_dirs ${more_pc_dirs})
string(REPLACE ";" ":" pc_path "${pc_dirs}")
set(ENV{PKG_CONFIG_PATH} "${pc_path}")
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${WORK_DIR}/build --output-on-failure
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the consumer's tests failed")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
