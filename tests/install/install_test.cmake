# `cmake --install` into a temporary prefix, then the installed binary on an installed case and
# `settle plot` from there (CTest: Install.InstalledBinaryRunsAndPlotsFromItsPrefix, label case).
# Everything is written under PREFIX (in the build tree), nothing in the source tree.
#   cmake -DBUILD_DIR=<build> -DPREFIX=<scratch prefix> -DPYTHON=/usr/bin/python3 -P install_test.cmake
foreach(var BUILD_DIR PREFIX PYTHON)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_test.cmake: -D${var}=... is required")
  endif()
endforeach()

function(require_files)
  foreach(file ${ARGN})
    if(NOT EXISTS ${PREFIX}/${file})
      message(FATAL_ERROR "missing after install: ${PREFIX}/${file}")
    endif()
  endforeach()
endfunction()

# Runs a command with SETTLE_PYTHON_DIR unset (the binary must find its scripts by itself) and
# fails with its output unless its exit status is `status`.
function(run_expecting status)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=SETTLE_PYTHON_DIR --unset=SETTLE_PYTHON
                          PYTHONDONTWRITEBYTECODE=1 OMP_NUM_THREADS=1 ${ARGN}
                  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL status)
    message(FATAL_ERROR "expected status ${status}, got ${result}: ${ARGN}\nstdout:\n${out}\nstderr:\n${err}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${PREFIX})
run_expecting(0 ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX})
set(python_dir share/settle/python)
require_files(bin/settle ${python_dir}/settle_plot.py ${python_dir}/settle_study_plot.py ${python_dir}/settle/__init__.py
              share/settle/cases/prolate_spheroid.toml share/settle/studies/window_width.toml
              share/doc/settle/user-guide.md share/doc/settle/README.md)

# A coarse tilted spheroid (5 cells per d_eq, 4 steps' worth of time): only the files matter here.
set(run ${PREFIX}/run)
run_expecting(0 ${PREFIX}/bin/settle run ${PREFIX}/share/settle/cases/prolate_spheroid.toml -o ${run}
              --set numerics.cells_per_diameter=5 --set run.end_time=0.002 --set run.output_interval=0.001
              --threads 1 --quiet)
foreach(file timeseries.csv summary.json case.resolved.toml)
  require_files(run/${file})
endforeach()

# settle plot's figures need matplotlib and numpy; without them the test is skipped (CTest's
# SKIP_REGULAR_EXPRESSION), as the plot case tests are.
execute_process(COMMAND ${PYTHON} -c "import matplotlib, numpy" RESULT_VARIABLE no_matplotlib OUTPUT_QUIET ERROR_QUIET)
if(no_matplotlib)
  message("SKIP: ${PYTHON} does not import matplotlib and numpy")
  return()
endif()
run_expecting(0 ${CMAKE_COMMAND} -E env SETTLE_PYTHON=${PYTHON} ${PREFIX}/bin/settle plot ${run})
foreach(figure velocity trajectory orientation forces)
  require_files(run/plots/${figure}.png)
endforeach()

# The installed package reads the run (when pandas is there: docs/python.md). Lines, not `;`:
# a `;` would split the CMake argument.
execute_process(COMMAND ${PYTHON} -c "import pandas" RESULT_VARIABLE no_pandas OUTPUT_QUIET ERROR_QUIET)
if(NOT no_pandas)
  run_expecting(0 ${CMAKE_COMMAND} -E env PYTHONPATH=${PREFIX}/${python_dir} ${PYTHON} -c
                "import settle\nr = settle.load_run('${run}')\nassert settle.__file__.startswith('${PREFIX}')\nprint(len(r.timeseries), r.timeseries.attrs['units']['uz'])")
  if(NOT last_output MATCHES "^[0-9]+ m/s")
    message(FATAL_ERROR "the installed package did not read the run: ${last_output}")
  endif()
endif()

# The scripts came from the prefix, not from the source tree the binary was built from: without
# the installed settle_plot.py the installed binary refuses, naming the installed folder.
file(REMOVE ${PREFIX}/${python_dir}/settle_plot.py)
run_expecting(2 ${CMAKE_COMMAND} -E env SETTLE_PYTHON=${PYTHON} ${PREFIX}/bin/settle plot ${run})
string(FIND "${last_output}" "${PREFIX}/${python_dir}" named)
if(named EQUAL -1)
  message(FATAL_ERROR "the refusal does not name ${PREFIX}/${python_dir}:\n${last_output}")
endif()
file(REMOVE_RECURSE ${PREFIX})
message("installed binary ran and plotted from ${PREFIX}")
