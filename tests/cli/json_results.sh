#!/usr/bin/env bash
# Issue 50: `--json` on every command that prints a result: stdout holds one
# JSON object (tests/cli/json_result.py) with the command's fields, whether
# --json comes before the command or after it; progress stays on stderr. A
# failure prints one object too, with its exit status. photograph, detect,
# fit and camera-intrinsics are checked in their loops
# (photo_calibration_loop.sh, camera_intrinsics_loop.sh).
# Usage: json_results.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
small="$examples/small/hybrid_small.json"
check="/usr/bin/python3 $(dirname "$0")/json_result.py"
# json NAME COMMAND... : run with --json after the command; stdout to NAME.json
json() {
  local name=$1
  shift
  "$layerlab" "$@" --json >"$work/$name.json" 2>"$work/log" || fail "layerlab $* --json exited with $?"
}

json help help
$check "$work/help.json" help commands.0.name=layerlab || fail "help"
"$layerlab" --json info "$small" >"$work/info.json" 2>"$work/log" || fail "layerlab --json info failed"
$check "$work/info.json" info layers || fail "info (--json before the command)"
json render render-target "$examples/small/small_dice_target.json" --out "$work/lf"
$check "$work/render.json" render-target "out=$work/lf" views=[5,5] rays || fail "render-target"
json solve solve "$small" --target "$work/lf" --iterations 2 --out "$work/s"
$check "$work/solve.json" solve "out=$work/s" report.iterations=2 report.final_psnr_db report.usable=true || fail "solve"
[ -s "$work/log" ] || fail "solve said nothing on stderr (progress belongs there)"
json retina retina "$small" --patterns "$work/s" --target "$work/lf" --accommodation 0.5:1.5:0.5 --resolution 0.5 \
  --out "$work/r"
$check "$work/retina.json" retina accommodation_diopters=[0.5,1.0,1.5] eyes.0.mean_against_natural.psnr_db \
  white_cd_per_m2 || fail "retina"
json contrast contrast "$small" --depths 1.3 --frequencies 1 --accommodation 2,0.5,1.5,1 --no-peak-uncertainty \
  --out "$work/c"
$check "$work/contrast.json" contrast peaks.0.display peaks.0.peak_diopters peaks.0.peak_uncertainty_diopters=null \
  || fail "contrast"
json eyebox eyebox "$small" --patterns "$work/s" --target "$work/lf" --accommodation 1 --eyebox-range "1 mm" --eyebox-step "1 mm" \
  --resolution 0.5 --out "$work/e"
$check "$work/eyebox.json" eyebox centre_psnr_db pupil_extent_within_quality_m || fail "eyebox"
json compare compare "$small" --solvers hybrid,quasi-newton --target "$work/lf" --iterations 1 --out "$work/m"
$check "$work/compare.json" compare runs.0.solver=hybrid runs.1.solver=quasi-newton runs.0.final_psnr_db \
  || fail "compare"
json psf psf "$small" --vergence 0,0.5 --frequencies 5 --size 31 --out "$work/p"
$check "$work/psf.json" psf eye files || fail "psf"
echo '{"panel_decentre": "0.2 mm"}' >"$work/tol.json"
json tolerance tolerance "$small" --tolerances "$work/tol.json" --samples 2 --no-psnr --out "$work/t"
$check "$work/tolerance.json" tolerance tolerance || fail "tolerance"
solve_only "$small" "$work/solve_only.json"
sed -i "s|\"small_dice_target.json\"|\"$examples/small/small_dice_target.json\"|" "$work/solve_only.json"
json run run "$work/solve_only.json" --iterations 1 --out "$work/run"
$check "$work/run.json" run index_html solve.final_psnr_db solve.iterations=1 || fail "run"
mkdir -p "$work/sweep"
cat >"$work/sweep/sweep.json" <<JSON
{"format": "layerlab-sweep/1", "scene": "$small", "work": ["solve"],
 "parameters": [{"name": "pupil", "pointer": "/elements/0/pupil_diameter", "values": ["3 mm", "5 mm"]}]}
JSON
json sweep sweep "$work/sweep/sweep.json" --slurm --out "$work/sweep/out"
$check "$work/sweep.json" sweep jobs=2 slurm_scripts submit || fail "sweep --slurm"
if "$layerlab" --json calibration-patterns --help >/dev/null 2>&1; then  # built with Ceres
  json plan calibration-patterns "$small" --out "$work/plan"
  $check "$work/plan.json" calibration-patterns photographs_to_take pattern_images || fail "calibration-patterns"
  json board camera-patterns --out "$work/board" --poses 4
  $check "$work/board.json" camera-patterns photographs_to_take=4 square_size_m || fail "camera-patterns"
fi

# Failures: one object with the error and the exit status, on stdout; the message on stderr as ever.
"$layerlab" info "$examples/no_such_scene.json" --json >"$work/missing.json" 2>"$work/log"
[ $? -eq 1 ] || fail "a missing scene did not exit 1"
$check "$work/missing.json" info exit_status=1 error || fail "the failure of info"
grep -q "^layerlab: error: .*no_such_scene.json" "$work/log" || fail "the failure is not on stderr"
"$layerlab" --json sovle >"$work/unknown.json" 2>"$work/log"
[ $? -eq 2 ] || fail "an unknown command did not exit 2"
$check "$work/unknown.json" "" exit_status=2 || fail "the failure of an unknown command"
echo "PASS: every command's --json is one object"
