# Shared by scripts/validate_mordant_pinton.sh and scripts/validate_uhlmann_dusek.sh (sourced, from
# the source tree's top folder). Environment: SETTLE, THREADS, RUNS_DIR (see those scripts).

# SETTLE: the given binary, or the native preset's, built first.
settle_binary() {
  if [[ -z "${SETTLE:-}" ]]; then
    cmake --preset native >/dev/null
    cmake --build --preset native --target settle_cli
    SETTLE=./build/native/src/app/settle
  fi
}

# run_validation_case NAME CELLS [extra `settle run` arguments...]: runs cases/NAME.toml at CELLS
# cells per diameter into RUNS_DIR/NAME_nCELLS, or at the case file's own resolution into
# RUNS_DIR/NAME when CELLS is "case" (the folder printed as the last line), records the wall time in
# wall_seconds.txt there, and writes `settle analyze` to analysis.txt (ANALYZE_ARGS: extra flags
# of `settle analyze`, e.g. "--window 3", which also set the figures merged into summary.json).
run_validation_case() {
  local name=$1 cells=$2 analyze_args
  shift 2
  read -ra analyze_args <<<"${ANALYZE_ARGS:-}"
  local dir="${RUNS_DIR:-runs}/${name}_n${cells}" start resolution=(--set "numerics.cells_per_diameter=${cells}")
  if [[ $cells == case ]]; then
    dir="${RUNS_DIR:-runs}/${name}"
    resolution=()
  fi
  echo "== ${name}, cells per diameter: ${cells} -> ${dir}" >&2
  start=$(date +%s)
  "${SETTLE}" run "cases/${name}.toml" -o "${dir}" "${resolution[@]}" --threads "${THREADS:-0}" "$@" >&2
  echo "$(($(date +%s) - start))" >"${dir}/wall_seconds.txt"
  "${SETTLE}" analyze "${dir}" "${analyze_args[@]}" | tee "${dir}/analysis.txt" >&2
  echo "${dir}"
}
