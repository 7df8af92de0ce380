#!/bin/sh
# layerlab sweep with retinal images: the base scene's run.retina.metrics
# (the reduced example asks for "ssim,jnd") become a column each in the
# table, the mean over the job's retina states of its retina.csv column.
. "$(dirname "$0")/sweep_common.sh"
sweep=$work/sweep.json
write_sweep "$sweep" '["solve", "retina"]' "[$PUPILS]"
"$layerlab" sweep "$sweep" --out "$work/out" >"$work/log" 2>&1 || { cat "$work/log"; fail "the sweep failed"; }
python3 - "$work/out" <<'PY' || fail "the table's metric columns are not the means of the jobs' retina.csv"
import csv, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(out + "/table.csv")))
assert len(rows) == 2, rows
for name, column in (("psnr", "psnr_db"), ("ssim", "ssim"), ("jnd", "jnd")):
    unit = {"psnr": "dB", "ssim": "1", "jnd": "JND"}[name]
    key = "focal-stack %s, mean over the retinal states (%s)" % (name, unit)
    assert key in rows[0], (key, list(rows[0]))
    for row in rows:
        states = list(csv.DictReader(open("%s/jobs/%s/out/retina/retina.csv" % (out, row["job"]))))
        mean = sum(float(s[column]) for s in states) / len(states)
        assert abs(float(row[key]) - mean) <= 1e-4 * max(1.0, abs(mean)), (name, row[key], mean)
assert not any("ms_ssim" in k for k in rows[0]), list(rows[0])
PY
echo "PASS"
