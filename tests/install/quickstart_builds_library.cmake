# The CTest test quickstart_builds_library: the README's `cmake --install build` follows the quick
# start, which builds only the `exao` target (scripts/quickstart.sh); the install then needs
# libexao.so, so building `exao` must build it (issue 22). Asks Ninja what cli/exao depends on.
# cmake -DBUILD_DIR=... -DGENERATOR=... -DNINJA=... -P quickstart_builds_library.cmake
if(NOT GENERATOR MATCHES "Ninja")
  message(STATUS "skipped: the check asks Ninja, the generator is ${GENERATOR}")
  return()
endif()
execute_process(COMMAND ${NINJA} -C ${BUILD_DIR} -t query cli/exao RESULT_VARIABLE status OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "ninja -t query cli/exao failed (${status}): ${err}")
endif()
if(NOT out MATCHES "api/libexao\\.so")
  message(FATAL_ERROR "building the exao target does not build api/libexao.so, which cmake --install needs:\n${out}")
endif()
