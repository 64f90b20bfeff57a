#!/usr/bin/env bash
# What a sweep's errors, charts and summary show, each number against an independent computation
# from runs.csv or the runs' own particle dumps (python3, no apiclab code):
# - errors at the run's precision: two double runs, one under a gravity of 1e-9 (a fall of 3e-11
#   in 0.25 s, about 1e-9 of the spin's displacement), read their distance from
#   `--dump-format csv` (17 digits), far below the float floor;
# - a record of the older float frames format is refused by --collect and recorded again on resume;
# - convergence lines never cross dt_factors (slopes refitted); failed runs on the error-against-
#   cost chart at its top edge; shapes and labels by configuration; the target line; the Pareto
#   front; the summary's reference, its cost and errors, and "no run meets it";
# - a refused run (a memory cap) makes the sweep exit 2 and is its own outcome in every table.
# Usage: APICLAB=/path/to/apiclab sweep_charts_tests.sh SOURCE_DIR
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: sweep_charts_tests.sh SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-sweep-charts.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# errors_of RUNS_CSV: each run's id and distances to its reference.
errors_of() {
  python3 -c "import csv,sys; [print(r['id'], *[r[k] for k in r if k.startswith('err_')]) for r in csv.DictReader(open(sys.argv[1]))]" "$1"
}

# --- Errors at the run's precision -------------------------------------------------------------
cat >"$TMP/prec.json" <<'JSON'
{"name": "prec", "scene": "rotating-disk",
 "set": {"time.end": 0.25, "time.fps": 8, "solver.integrator": "symplectic",
         "time.dt.rule": "elastic", "time.dt.nu": 0.5, "domain.dx": 0.0625},
 "axes": {"gravity.1": [0, -1e-9]}, "reference": {"gravity.1": 0}}
JSON
if "$APICLAB" sweep "$TMP/prec.json" --out "$TMP/prec" --jobs 2 --quiet --dump-format csv \
  >"$TMP/out" 2>"$TMP/err"; then
  # The relative L2 displacement error over frames and particles, from the CSV dumps in double
  # and rounded to float (what frames.bin held before); the same material points (one sampling).
  got=$(python3 - "$TMP/prec" <<'PY'
import csv, glob, math, os, struct, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "runs.csv"))))
ref = next(r for r in rows if r["id"] == r["reference"])
run = next(r for r in rows if r["id"] != r["reference"])
def frames(rid):
    fs = []
    for f in sorted(glob.glob(os.path.join(out, "runs", rid, "dump", "frame_*.csv"))):
        pts = {}
        for r in csv.DictReader(open(f)):
            pts[int(r["id"])] = (float(r["x"]), float(r["y"]))
        fs.append(pts)
    return fs
def f32(v): return struct.unpack("f", struct.pack("f", v))[0]
def err(a, b, rnd):
    num = den = 0.0
    for fa, fb in zip(a, b):
        for q in fb:
            for k in range(2):
                u = rnd(fa[q][k]) - rnd(a[0][q][k]); ur = rnd(fb[q][k]) - rnd(b[0][q][k])
                num += (u - ur) ** 2; den += ur ** 2
    return math.sqrt(num) / math.sqrt(den)
a, b = frames(run["id"]), frames(ref["id"])
assert len(a) == len(b) == 3, (len(a), len(b))
print(run["err_displacement"], err(a, b, float), err(a, b, f32))
PY
)
  read -r sweep_err dbl flt <<<"$got"
  if python3 -c "import sys; s,d,f=map(float,sys.argv[1:]); sys.exit(0 if 0<d<1e-8 and abs(s-d)<=1e-4*d and abs(f-d)>0.5*d else 1)" \
    "$sweep_err" "$dbl" "$flt" 2>/dev/null; then
    ok "errors at the run's precision: a 1e-9 gravity reads $sweep_err (double dumps $dbl; as floats $flt)"
  else
    nok "errors at the run's precision (runs.csv '$sweep_err', double dumps '$dbl', floats '$flt')" \
      "$(cat "$TMP/err")"
  fi
  # An older record (frames.bin with 32-bit positions) is never read beside double ones.
  cp "$TMP/prec/runs.csv" "$TMP/prec-runs.csv"
  run_id=$(python3 -c "import csv,sys; print(next(r['id'] for r in csv.DictReader(open(sys.argv[1])) if r['id'] != r['reference']))" "$TMP/prec/runs.csv")
  python3 - "$TMP/prec/runs/$run_id/frames.bin" <<'PY'
import struct, sys
p = sys.argv[1]; b = open(p, "rb").read()
assert b[:4] == b"ASF2"
dim, size, n = struct.unpack_from("<iiQ", b, 4)
o = 4 + 16; objects = b[o:o + 4 * n]; o += 4 * n
out = b"ASF1" + struct.pack("<iQ", dim, n) + objects
while o < len(b):
    out += b[o:o + 24]; o += 24
    xs = struct.unpack_from("<%dd" % (n * dim), b, o); o += 8 * n * dim
    out += struct.pack("<%df" % (n * dim), *xs)
open(p, "wb").write(out)
PY
  "$APICLAB" sweep "$TMP/prec.json" --collect "$TMP/prec" >"$TMP/out" 2>"$TMP/err"
  rc=$?
  if [ $rc -eq 2 ] && [ "$(wc -l <"$TMP/err")" -eq 1 ] &&
    grep -q "frames.bin: recorded by an older apiclab with positions as 32-bit floats" "$TMP/err"; then
    ok "--collect refuses a record of the older float frames format (exit 2, one line)"
  else
    nok "--collect of an older record (rc $rc)" "$(cat "$TMP/err")"
  fi
  if "$APICLAB" sweep "$TMP/prec.json" --out "$TMP/prec" --dump-format csv >"$TMP/out" 2>"$TMP/err" &&
    grep -q "1 runs recorded by an older apiclab (positions as 32-bit floats) run again" "$TMP/err" &&
    [ "$(head -c 4 "$TMP/prec/runs/$run_id/frames.bin")" = "ASF2" ] &&
    [ "$(errors_of "$TMP/prec/runs.csv")" = "$(errors_of "$TMP/prec-runs.csv")" ]; then
    ok "resume records the older run again at the run's precision: the same errors"
  else
    nok "resume of an older record" "$(cat "$TMP/err")"
  fi
else
  nok "precision sweep exited $?" "$(cat "$TMP/err")"
fi

# --- A refused run ------------------------------------------------------------------------------
# CSV dumps need particles: the EoL run's process refuses them (exit 2) after the plan.
cat >"$TMP/refused.json" <<'JSON'
{"name": "refused", "scene": "eol-spin", "set": {"time.end": 0.05},
 "axes": {"solver.method": ["mpm", "eol"]}, "reference": {"solver.method": "mpm"}}
JSON
"$APICLAB" sweep "$TMP/refused.json" --out "$TMP/refused" --jobs 2 --quiet --dump-format csv \
  >"$TMP/out" 2>"$TMP/err"
rc=$?
R=$TMP/refused
if [ $rc -eq 2 ] && tail -n 1 "$TMP/err" | grep -q "^apiclab: sweep: 1 of 2 runs refused" &&
  [ "$(grep -c ',refused,' "$R/runs.csv")" -eq 1 ] && grep -q '^exit 2: apiclab: --dump' "$R"/runs/*/refused.txt; then
  ok "a refused run: the sweep writes everything, then exits 2 naming it; outcome refused"
else
  nok "a refused run (rc $rc)" "$(cat "$TMP/err")" "$(cat "$R/runs.csv" 2>/dev/null)"
fi
if grep -q 'refused, exit 2' "$R/stability_eol-spin.csv" 2>/dev/null &&
  grep -q '^## Refused runs' "$R/summary.md" && grep -q 'refused, exit 2' "$R/summary.md" &&
  grep -q '^[0-9a-f]*,all,refused,,,0.001,1,0,' "$R/error_vs_cost_eol-spin.csv"; then
  ok "a refused run: its cell in the stability map, a summary section, a point at the chart's top left"
else
  nok "a refused run in the map, summary and chart" "$(cat "$R/stability_eol-spin.csv" "$R/error_vs_cost_eol-spin.csv" 2>/dev/null)"
fi

# --- Charts and summary ------------------------------------------------------------------------
# dt_factor 4 blows up with symplectic Euler; the reference: resolution 1, dt_factor 0.25.
cat >"$TMP/charts.json" <<'JSON'
{"name": "charts", "scene": "rotating-disk",
 "set": {"time.end": 0.25, "time.fps": 8, "solver.integrator": "symplectic"},
 "axes": {"dt_factor": [0.25, 0.5, 4], "resolution": [0.5, 0.75, 1]}}
JSON
if ! "$APICLAB" sweep "$TMP/charts.json" --out "$TMP/charts" --jobs 2 --quiet --target-error 1e-12 \
  >"$TMP/out" 2>"$TMP/err"; then
  nok "charts sweep exited $?" "$(cat "$TMP/err")"
fi

# Every number of the charts and the summary, recomputed from runs.csv.
if [ -s "$TMP/charts/error_vs_cost_rotating-disk.csv" ]; then
  python3 - "$TMP/charts" >"$TMP/py" 2>&1 <<'PY'
import csv, math, os, sys
out = sys.argv[1]
runs = {r["id"]: r for r in csv.DictReader(open(os.path.join(out, "runs.csv")))}
cost = list(csv.DictReader(open(os.path.join(out, "error_vs_cost_rotating-disk.csv"))))
conv = list(csv.DictReader(open(os.path.join(out, "convergence_rotating-disk.csv"))))
summary = open(os.path.join(out, "summary.md")).read()
fails = []
def check(cond, what):
    if not cond: fails.append(what)
def close(a, b, rel=1e-5):
    return abs(float(a) - float(b)) <= rel * max(abs(float(a)), abs(float(b)), 1e-300)
num = lambda s: float(s) if s != "" else float("nan")
# Error against cost: every run but the reference, once, where it belongs.
points = [r for r in cost if r["id"] != "target"]
ref = {r["reference"] for r in runs.values()}
check(sorted(p["id"] for p in points) == sorted(i for i in runs if i not in ref), "runs on the chart")
drawn = [p for p in points if runs[p["id"]]["outcome"] in ("completed", "noisy", "not_converged")]
for p in drawn:
    r = runs[p["id"]]
    check(close(p["plotted_cost_s"], r["step_wall_s"]) and close(p["plotted_error"], r["err_displacement"]),
          "point " + p["id"])
top = 3 * max([num(p["plotted_error"]) for p in drawn] + [1e-12])
blew = [p for p in points if runs[p["id"]]["outcome"] == "blew_up"]
refused = [p for p in points if runs[p["id"]]["outcome"] == "refused"]
check(len(blew) == 3 and len(refused) == 0, "failed runs on the chart: %d blew up, %d refused" % (len(blew), len(refused)))
for p in blew:
    check(close(p["plotted_error"], top) and close(p["plotted_cost_s"], runs[p["id"]]["step_wall_s"]),
          "blown-up run at the top edge " + p["id"])
x_lo = min([num(p["plotted_cost_s"]) for p in drawn + blew])
for p in refused:
    check(close(p["plotted_error"], top) and close(p["plotted_cost_s"], x_lo), "refused run at the top left " + p["id"])
target = [r for r in cost if r["id"] == "target"]
check(len(target) == 1 and close(target[0]["plotted_error"], 1e-12), "target line")
# Shapes by dt_factor, labels by resolution.
for p in points:
    r = runs[p["id"]]
    check(p["shape"] == "dt_factor=" + r["dt_factor"] and p["point_label"] == r["resolution"],
          "marking of " + p["id"] + ": " + p["shape"] + " / " + p["point_label"])
# Pareto front: completed or noisy, not dominated in (cost, error).
cand = [p for p in drawn if runs[p["id"]]["outcome"] in ("completed", "noisy")]
cand.sort(key=lambda p: (num(p["plotted_cost_s"]), num(p["plotted_error"])))
front, best = set(), float("inf")
for p in cand:
    if num(p["plotted_error"]) < best:
        best = num(p["plotted_error"]); front.add(p["id"])
check({p["id"] for p in points if p["pareto"] == "1"} == front, "Pareto front")
# Convergence: one dt_factor per line, each line's slope refitted.
series = {}
for c in conv:
    series.setdefault(c["series"], []).append(c)
check(len(series) == 2, "convergence lines: %s" % sorted(series))
for name, pts in series.items():
    check(len({runs[c["id"]]["dt_factor"] for c in pts}) == 1, "line " + name + " crosses dt_factors")
    xs = [math.log(float(runs[c["id"]]["dx"])) for c in pts]
    ys = [math.log(float(runs[c["id"]]["err_displacement"])) for c in pts]
    n = len(xs); mx = sum(xs) / n; my = sum(ys) / n
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    check(n >= 2 and close(pts[0]["slope"], slope, 1e-3), "slope of " + name)
# Summary: the reference, its cost and own errors; nothing meets 1e-12, said plainly.
(rid,) = ref
r = runs[rid]
line = next((l for l in summary.splitlines() if "(run %s)" % rid in l and "own errors" in l), "")
check(("%.3g s in the steps" % float(r["step_wall_s"])) in line and
      ("max |dE|/E0 %.3g" % float(r["max_energy"])) in line, "reference line: " + line)
closest = min((num(x["err_displacement"]), i) for i, x in runs.items()
              if x["outcome"] == "completed" and i not in ref)
check("no run meets it; the closest completed run" in summary and
      ("(run %s), reaches %.3g" % (closest[1], closest[0])) in summary and
      "the reference meets it" not in summary, "target answer")
# The summary's Pareto table: the same runs by cost, cost and error to 3 digits.
sec = summary.split("## Pareto front: rotating-disk")[1].split("\n## ")[0]
got = [tuple(c.strip() for c in l.split("|")[2:4]) for l in sec.splitlines()
       if l.startswith("| ") and "configuration" not in l]
want = [("%.3g" % num(runs[i]["step_wall_s"]), "%.3g" % num(runs[i]["err_displacement"]))
        for i in sorted(front, key=lambda i: num(runs[i]["step_wall_s"]))]
check(got == want, "summary Pareto table %s against %s" % (got, want))
# The stability map's cells: rows by resolution, columns by dt_factor.
table = list(csv.reader(open(os.path.join(out, "stability_rotating-disk.csv"))))
head = table[0]
for i, r in runs.items():
    row = next(t for t in table[1:] if t[0] == r["resolution"])
    cell = row[head.index("dt_factor=" + r["dt_factor"])]
    if r["outcome"] == "completed":
        want_cell = "completed dE %.3g%%" % (100 * float(r["final_energy"]))
    else:
        want_cell = "blew_up blew up t=%.2g" % float(r["fail_t"])
    check(cell == want_cell, "stability cell %s: %s, want %s" % (i, cell, want_cell))
print("\n".join(fails) if fails else "all")
PY
  if [ "$(cat "$TMP/py")" = "all" ]; then
    ok "charts and summary: every point, edge, shape, label, front, slope, map cell and the reference recomputed"
  else
    nok "charts and summary against runs.csv" "$(cat "$TMP/py")"
  fi
else
  nok "no error-against-cost CSV" "$(ls "$TMP/charts")"
fi

finish sweep_charts_tests
