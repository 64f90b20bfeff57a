#!/usr/bin/env bash
# No silent contradictions (docs/cli.md, docs/sweeps.md): an option and a `--set` of its key, or
# one key set twice, that disagree exit 2 naming both, and are accepted where they agree; a
# sweep spec with a key written twice, or a key in both `set` and the axes, exits 2 naming it;
# every frame time up to time.end gets its frame, with adaptive and fixed steps.
# Usage: APICLAB=/path/to/apiclab contradiction_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-contra.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# refused NAME NEEDLE... -- ARGS: exit 2, one stderr line holding every needle, no CSV written.
refused() {
  local name=$1 needles=()
  shift
  while [ "$1" != "--" ]; do needles+=("$1") && shift; done
  shift
  rm -rf "$TMP/out.csv"
  timeout 20 "$APICLAB" "$@" --csv "$TMP/out.csv" --quiet >/dev/null 2>"$TMP/err"
  local rc=$? lines good=1
  lines=$(wc -l <"$TMP/err")
  for n in "${needles[@]}"; do grep -qF -- "$n" "$TMP/err" || good=0; done
  if [ $rc -eq 2 ] && [ "$lines" -eq 1 ] && [ $good = 1 ] && [ ! -s "$TMP/out.csv" ]; then
    ok "$name"
  else
    nok "$name (rc $rc, $lines lines, wanted: ${needles[*]})" "$(cat "$TMP/err")"
  fi
}
accepted() {
  local name=$1
  shift
  rm -f "$TMP/ok.csv" "$TMP/ok.csv.json"  # each case a run of its own (outputs are owned)
  if timeout 60 "$APICLAB" "$@" --csv "$TMP/ok.csv" --quiet >/dev/null 2>"$TMP/err"; then
    ok "$name"
  else
    nok "$name (rc $?)" "$(cat "$TMP/err")"
  fi
}

D=(run rotating-disk)
refused "--scheme against --set solver.scheme" "--set solver.scheme=flip" "--scheme pic" \
  "solver.scheme" -- "${D[@]}" --set solver.scheme=flip --scheme pic
refused "--t-end against --set time.end" "--set time.end=5" "--t-end 0.1" "time.end" -- \
  "${D[@]}" --set time.end=5 --t-end 0.1
refused "one key set twice by --set" "--set time.end=5" "--set time.end=0.1" -- \
  "${D[@]}" --set time.end=5 --set time.end=0.1
refused "--frames against --set time.end" "--frames 2" "--set time.end=5" -- \
  "${D[@]}" --frames 2 --set time.end=5
refused "--dt against --set time.dt.value" "--dt 0.001" "--set time.dt.value=0.002" -- \
  "${D[@]}" --dt 0.001 --set time.dt.value=0.002
refused "--set of a section that drops an option's key" "--dt 0.001" '--set time.dt={"rule":"cfl"}' -- \
  "${D[@]}" --dt 0.001 --set 'time.dt={"rule":"cfl"}'
refused "--lambda against --set solver.integrator" "--set solver.integrator=midpoint" "--lambda 0.25" -- \
  "${D[@]}" --set solver.integrator=midpoint --lambda 0.25
refused "--fps against --set time.fps" "--fps 30" "--set time.fps=24" -- \
  "${D[@]}" --fps 30 --set time.fps=24
accepted "an option and --set that agree, a key set twice to one value" "${D[@]}" --scheme pic \
  --set solver.scheme=pic --t-end 0.01 --set time.end=0.01 --set time.end=0.01
accepted "--dt with a key its value lacks (time.dt.land_on_frames)" "${D[@]}" --t-end 0.01 \
  --dt 0.005 --set time.dt.land_on_frames=true --set time.dt.value=0.005

# Sweep specs: a key written twice, a key in both set and the axes.
spec_refused() {
  local name=$1 json=$2
  shift 2
  printf '%s\n' "$json" >"$TMP/spec.json"
  rm -rf "$TMP/sweep"
  timeout 20 "$APICLAB" sweep "$TMP/spec.json" --out "$TMP/sweep" >/dev/null 2>"$TMP/err"
  local rc=$? lines good=1
  lines=$(wc -l <"$TMP/err")
  for n in "$@"; do grep -qF -- "$n" "$TMP/err" || good=0; done
  if [ $rc -eq 2 ] && [ "$lines" -eq 1 ] && [ $good = 1 ] && [ ! -e "$TMP/sweep/runs" ]; then
    ok "sweep: $name"
  else
    nok "sweep: $name (rc $rc, $lines lines, wanted: $*)" "$(cat "$TMP/err")"
  fi
}
S='"scene": "rotating-disk"'
spec_refused "a top-level key twice" "{$S, \"name\": \"a\", \"name\": \"b\", \"axes\": {\"solver.scheme\": [\"pic\"]}}" \
  "key 'name' appears twice"
spec_refused "an axis twice" "{$S, \"axes\": {\"solver.scheme\": [\"pic\"], \"solver.scheme\": [\"apic\"]}}" \
  "key 'axes.solver.scheme' appears twice"
spec_refused "a set key twice" "{$S, \"set\": {\"time.end\": 0.1, \"time.end\": 5}, \"axes\": {\"solver.scheme\": [\"pic\"]}}" \
  "key 'set.time.end' appears twice"
spec_refused "a key in both set and axes" "{$S, \"set\": {\"solver.scheme\": \"flip\"}, \"axes\": {\"solver.scheme\": [\"pic\", \"apic\"]}}" \
  "key 'solver.scheme'" "in both \"set\" and the axis 'solver.scheme'"
spec_refused "a zipped axis and set" "{$S, \"set\": {\"time.end\": 0.1}, \"zip\": [{\"time.end\": [0.1, 0.2], \"solver.scheme\": [\"pic\", \"apic\"]}]}" \
  "in both \"set\" and the axis 'time.end'"
spec_refused "dt_factor and set time.dt.value" "{$S, \"set\": {\"time.dt.value\": 0.001}, \"axes\": {\"dt_factor\": [0.5, 1]}}" \
  "key 'time.dt.value'" "the axis 'dt_factor'"
spec_refused "resolution and set domain.dx" "{$S, \"set\": {\"domain.dx\": 0.05}, \"axes\": {\"resolution\": [0.5, 1]}}" \
  "key 'domain.dx'" "the axis 'resolution'"

# Frames: floor(time.end x fps) + 1, plus time.end itself when it falls between frame times.
# frames_at NAME "T0 T1 ..." ARGS: frames.csv holds exactly these times (to 1e-12), one file each.
frames_at() {
  local name=$1 want=$2
  shift 2
  rm -rf "$TMP/dump" "$TMP/f.csv" "$TMP/f.csv.json"  # each case a run of its own
  if ! "$APICLAB" run rotating-disk "$@" --dump "$TMP/dump" --csv "$TMP/f.csv" \
    --quiet >/dev/null 2>"$TMP/err"; then
    nok "$name (rc $?)" "$(cat "$TMP/err")"
    return
  fi
  local got
  got=$(tail -n +2 "$TMP/dump/frames.csv" | cut -d, -f2 | tr '\n' ' ')
  if awk -v got="$got" -v want="$want" 'BEGIN {
      n = split(got, g, " "); m = split(want, w, " "); if (n != m) exit 1
      for (i = 1; i <= n; i++) { split(w[i], q, "/"); t = (2 in q) ? q[1] / q[2] : q[1]
        if (g[i] - t > 1e-12 || t - g[i] > 1e-12) exit 1 }
    }' && [ "$(ls "$TMP/dump"/frame_*.csv | wc -l)" -eq "$(echo "$want" | wc -w)" ]; then
    ok "$name"
  else
    nok "$name" "frames.csv times: $got" "wanted: $want"
  fi
}
T=(--t-end 0.1)
frames_at "--t-end 0.1 at 24 fps, adaptive (cfl): 0, 1/24, 2/24 and 0.1" "0 1/24 2/24 0.1" "${T[@]}"
frames_at "--t-end 0.1 at 24 fps, the elastic rule" "0 1/24 2/24 0.1" "${T[@]}" \
  --set 'time.dt={"rule":"elastic","nu":0.3}'
frames_at "--t-end 0.1 at 24 fps, a fixed step that divides the frame interval" "0 1/24 2/24 0.1" \
  "${T[@]}" --dt 0.004166666666666667
frames_at "--t-end 0.1 at 24 fps, a fixed step landing on frames" "0 1/24 2/24 0.1" "${T[@]}" \
  --dt 0.03 --set time.dt.land_on_frames=true
frames_at "--t-end 1/12 at 24 fps: a whole number of frames, no extra one" "0 1/24 2/24" \
  --t-end 0.08333333333333333
# The fixed step taken exactly: each frame is the step at or just past its time.
frames_at "--t-end 0.1 at 24 fps, a fixed step of 0.03 s: the step at or just past" \
  "0 0.06 0.09 0.12" "${T[@]}" --dt 0.03

finish contradiction_tests
