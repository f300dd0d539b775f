# The installed package as a consumer meets it (ctest: Package.InstallFindPackageBuildAndRun).
#
#   cmake -DBUILD_DIR=… -DSOURCE_DIR=… -DWORK_DIR=… [-DCONFIG=…] [-DCXX_COMPILER=…]
#         [-DCXX_COMPILER_LAUNCHER=ccache] -P tests/package/consumer_test.cmake
#
# 1. `cmake --install BUILD_DIR --prefix WORK_DIR/prefix` into an emptied prefix: the library,
#    the public headers (and no internal one), version.hpp, the CLI, the CMake config and version
#    files, the pkg-config file, the example assembly and the LICENSE must be there.
# 2. examples/cpp/ configured against that prefix alone (find_package(toolpoint 0.1 REQUIRED)),
#    built, and run: the lobes from the example assembly, and the holder–tool joint identified from
#    two CSV files that the installed CLI writes (noise-free model FRFs, so the joint must come back
#    as the file's Table 1 values to the 6 digits printed: Eq. 6 is exact, the read-out a median).
# 3. pkg-config: a one-file program compiled and linked with only `pkg-config --cflags --libs
#    toolpoint` (it calls the SIMD sweep and the TOML reader, so SLEEF, fmt and toml++ must link).
# Paths are fixed under WORK_DIR (in the build tree), so ccache serves repeated runs.
cmake_minimum_required(VERSION 3.21)

foreach(var BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "consumer_test.cmake: -D${var}=… is required")
  endif()
endforeach()
if(NOT CONFIG)
  set(CONFIG Release)
endif()

function(run)
  cmake_parse_arguments(R "" "WORKING_DIRECTORY;OUTPUT" "COMMAND" ${ARGN})
  if(NOT R_WORKING_DIRECTORY)
    set(R_WORKING_DIRECTORY ${WORK_DIR})
  endif()
  execute_process(COMMAND ${R_COMMAND} WORKING_DIRECTORY ${R_WORKING_DIRECTORY}
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    list(JOIN R_COMMAND " " shown)
    message(FATAL_ERROR "failed (${code}): ${shown}\n--- stdout\n${out}\n--- stderr\n${err}")
  endif()
  if(R_OUTPUT)
    set(${R_OUTPUT} "${out}" PARENT_SCOPE)
  endif()
endfunction()

function(expect_match text regex what)
  if(NOT text MATCHES "${regex}")
    message(FATAL_ERROR "${what}: '${regex}' not found in:\n${text}")
  endif()
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${prefix} ${WORK_DIR}/run)
file(MAKE_DIRECTORY ${WORK_DIR}/run)

# ---- 1. Install ------------------------------------------------------------------------------------
run(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})
include(GNUInstallDirs)  # the same default directories as the project's install (lib, include, bin, share)
file(GLOB_RECURSE pc_files ${prefix}/*/toolpoint.pc)
file(GLOB_RECURSE config_files ${prefix}/*/toolpointConfig.cmake)
file(GLOB_RECURSE archives ${prefix}/*/libtoolpoint.a)
foreach(list pc_files config_files archives)
  list(LENGTH ${list} n)
  if(NOT n EQUAL 1)
    message(FATAL_ERROR "install: expected one ${list} under ${prefix}, found ${n}: ${${list}}")
  endif()
endforeach()
get_filename_component(config_dir ${config_files} DIRECTORY)
foreach(f ${config_dir}/toolpointConfigVersion.cmake ${config_dir}/toolpointTargets.cmake
          ${prefix}/bin/toolpoint ${prefix}/include/toolpoint/version.hpp ${prefix}/include/toolpoint/model/assembly.hpp
          ${prefix}/include/toolpoint/json.hpp ${prefix}/include/toolpoint/studies/overhang.hpp
          ${prefix}/share/toolpoint/bt40_shrinkfit_16mm.toml ${prefix}/share/doc/toolpoint/LICENSE)
  if(NOT EXISTS ${f})
    message(FATAL_ERROR "install: ${f} is missing")
  endif()
endforeach()
file(GLOB_RECURSE internal ${prefix}/include/*complex_pairs* ${prefix}/include/*lanes*)
if(internal)
  message(FATAL_ERROR "install: internal headers installed: ${internal}")
endif()
run(COMMAND ${prefix}/bin/toolpoint --version OUTPUT version)
file(READ ${prefix}/include/toolpoint/version.hpp version_hpp)
string(REGEX MATCH "TOOLPOINT_VERSION \"([0-9.]+)\"" _ "${version_hpp}")
expect_match("${version}" "toolpoint ${CMAKE_MATCH_1}" "installed CLI --version against version.hpp")

# ---- 2. A CMake consumer: examples/cpp ---------------------------------------------------------
set(consumer ${WORK_DIR}/consumer)
set(configure_args -S ${SOURCE_DIR}/examples/cpp -B ${consumer} -DCMAKE_BUILD_TYPE=Release
                   -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON)
if(CXX_COMPILER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
if(CXX_COMPILER_LAUNCHER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_COMPILER_LAUNCHER})
endif()
run(COMMAND ${CMAKE_COMMAND} ${configure_args})
# The consumer must have found the install, not a build tree or another copy.
file(STRINGS ${consumer}/CMakeCache.txt found_dir REGEX "^toolpoint_DIR:")
expect_match("${found_dir}" "${prefix}/" "find_package(toolpoint) location")
run(COMMAND ${CMAKE_COMMAND} --build ${consumer} -j 2)

set(example ${prefix}/share/toolpoint/bt40_shrinkfit_16mm.toml)
run(COMMAND ${consumer}/tool_point_to_lobes ${example} OUTPUT lobes)
expect_match("${lobes}" "tool point modes \\(peaks of \\|H\\|\\): 916 Hz 1600 Hz 2585 Hz" "tool_point_to_lobes modes")
expect_match("${lobes}" "absolute stability limit [0-9]+\\.[0-9]+ mm" "tool_point_to_lobes")
expect_match("${lobes}" "rpm  [0-9]+\\.[0-9]+ mm" "tool_point_to_lobes pockets")

set(run_dir ${WORK_DIR}/run)
run(COMMAND ${prefix}/bin/toolpoint --quiet predict ${example} --at holder --frequencies 2000:3200:5 --output sh.csv
    WORKING_DIRECTORY ${run_dir})
run(COMMAND ${prefix}/bin/toolpoint --quiet predict ${example} --frequencies 2000:3200:5 --output sht.csv
    WORKING_DIRECTORY ${run_dir})
run(COMMAND ${consumer}/identify_joint ${example} sh.csv sht.csv WORKING_DIRECTORY ${run_dir} OUTPUT joint)
# The example file's [joints.holder_tool]: the seed's Table 1.
foreach(expected "k_yf +4\\.19e\\+07 " "c_yf +54 " "k_ym +2\\.06e\\+06 " "k_tm +65000 ")
  expect_match("${joint}" "${expected}" "identify_joint (noise-free data give back the file's joint)")
endforeach()
# The library's band rule (the measured peak nearest the mode effect analysis names) and its verdict.
expect_match("${joint}" "effect analysis on the model" "identify_joint's band choice")
expect_match("${joint}" "verdict: pass" "identify_joint's verdict")

# ---- 3. A pkg-config consumer --------------------------------------------------------------------
get_filename_component(pc_dir ${pc_files} DIRECTORY)
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${pc_dir})
run(COMMAND ${PKG_CONFIG} --cflags toolpoint OUTPUT cflags)
run(COMMAND ${PKG_CONFIG} --libs toolpoint OUTPUT libs)
separate_arguments(cflags UNIX_COMMAND "${cflags}")
separate_arguments(libs UNIX_COMMAND "${libs}")
if(NOT CXX_COMPILER)
  set(CXX_COMPILER c++)
endif()
# Compile and link apart, as a build system would (and so ccache can serve the compile).
run(COMMAND ${CXX_COMPILER_LAUNCHER} ${CXX_COMPILER} -std=c++20 -O1 ${cflags} -c ${SOURCE_DIR}/tests/package/pkg_config_consumer.cpp
            -o ${WORK_DIR}/pkg_config_consumer.o)
run(COMMAND ${CXX_COMPILER} ${WORK_DIR}/pkg_config_consumer.o -o ${WORK_DIR}/pkg_config_consumer ${libs})
run(COMMAND ${WORK_DIR}/pkg_config_consumer ${example} OUTPUT pc_out)
expect_match("${pc_out}" "tool point \\|H\\| at 2585 Hz: [0-9.]+e-0[0-9] m/N" "pkg_config_consumer")
message(STATUS "installed package: CMake and pkg-config consumers built and ran")
