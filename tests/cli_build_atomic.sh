#!/usr/bin/env bash
# Atomic outputs under SIGKILL (issue 9, SPEC §11): `skyfit build` is killed
# at random moments (seeded, printed) over a whole run, the write phases
# included, and after every kill each file in the output folder must be
# byte-identical to either its complete previous version or its complete
# new version, never partial; no previous output may have vanished; the
# only other files allowed are the temporaries of the write that was
# interrupted ("NAME.tmp.PID.XXXXXX", util/atomic_file.h), which the next
# run that writes NAME removes, and the killed run's staging folder
# (".staging.PID/", fit/build_staging.h), which the next build removes. The
# outputs (all but the cache) must be all old, but for kills during the
# final burst of renames (at most 2 tolerated). A rerun after a kill
# completes and leaves exactly the new version (no temporaries).
#
# The scene's viewers fly (1-20 km), so the slow ground-only Preetham and
# Hosek fits stay out and a build takes about two seconds; its outputs are
# every kind skyfit writes: EXR tables, cached fits and timings, weights,
# headers, report, metrics, PNG views and EXR error maps.
# Versions: "old" is a complete build with seed 1 and scattering tables
# 8x16x8x4; "new" a complete build over it with seed 2 and 8x16x8x6, so
# tables, fits, weights, headers, report and views all differ. Both are
# kept from uninterrupted runs and compared with cmp. Timings are cached
# (DIR/cache/costs) and the new run's timings are copied in before each
# killed run, so a completed new run reproduces the new version byte for
# byte. Half of the kills land at a uniform random delay over the run; the
# other half wait a random delay in its second half (where the views,
# report and headers are written), then poll (no inotify) until a
# temporary exists, i.e. a file is being written, and kill then. If no
# kill landed mid-write (delays outrun on a loaded machine), polling kills
# from the start follow until one does (at most 4).
# SKYFIT_ATOMIC_SEED and SKYFIT_ATOMIC_TRIALS override the seed and count.
set -u
BIN=${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}
tmp=$(mktemp -d)
pid=
cleanup() {
  [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
seed=${SKYFIT_ATOMIC_SEED:-9091}
trials=${SKYFIT_ATOMIC_TRIALS:-16}
RANDOM=$seed
echo "seed $seed, $trials kills"
failures=0
pass() { echo "ok   $*"; }
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
shopt -s nullglob

cat >"$tmp/scene.json" <<'EOF'
{"name": "atomic", "viewer_altitude_km": [1, 20], "view": "all", "sun_elevation_deg": [-10, 90],
 "quantities": ["transmittance", "sky_radiance"],
 "error_budget": {"transmittance_rmse": 1e-3, "sky_radiance_rel_rmse": 0.05}}
EOF
D=$tmp/out
common=(--views 32x18 --samples 1000 --timing-points 5000 --repetitions 1 --mlp-epochs 20,2 --mlp-samples 2000
        --quick --quiet)
old_args=(--resolution 32x16,8x16x8x4 --seed 1)
new_args=(--resolution 32x16,8x16x8x6 --seed 2)
build() { "$BIN" build "$tmp/scene.json" --out "$D" "${common[@]}" "$@"; }
now_ms() { echo $(( ${EPOCHREALTIME/./} / 1000 )); }
is_temp() { [[ $1 =~ \.tmp\.[0-9]+\.[A-Za-z0-9]{6}$ ]]; }

# The two complete versions, from uninterrupted runs.
build "${old_args[@]}" >"$tmp/log" 2>&1 || { cat "$tmp/log"; echo "FAIL old build"; exit 1; }
cp -a "$D" "$tmp/old"
build "${new_args[@]}" >"$tmp/log" 2>&1 || { cat "$tmp/log"; echo "FAIL new build"; exit 1; }
cp -a "$D" "$tmp/new"
# Start of every killed run: the old version plus the new run's timings.
cp -a "$tmp/old" "$tmp/start"
cp -n "$tmp/new/cache/costs/"* "$tmp/start/cache/costs/"
n_old=$(find "$tmp/start" -type f | wc -l)
n_new=$(find "$tmp/new" -type f | wc -l)
n_changed=0
while IFS= read -r -d '' f; do
  rel=${f#"$tmp/new/"}
  cmp -s "$f" "$tmp/start/$rel" 2>/dev/null || n_changed=$((n_changed + 1))
done < <(find "$tmp/new" -type f -print0)
echo "old version: $n_old files; new version: $n_new files, $n_changed of them new or different"
[ "$n_changed" -ge 20 ] || fail "only $n_changed files differ between the versions (want >= 20)"

# An uninterrupted new run from the start state gives the new version and
# its duration, over which the kills are spread.
rm -rf "$D"; cp -a "$tmp/start" "$D"
t0=$(now_ms)
build "${new_args[@]}" >"$tmp/log" 2>&1 || { cat "$tmp/log"; echo "FAIL timed build"; exit 1; }
run_ms=$(( $(now_ms) - t0 ))
if diff -r "$D" "$tmp/new" >"$tmp/diff"; then
  pass "uninterrupted new run from the start state: identical to the new version ($run_ms ms)"
else
  fail "uninterrupted new run differs from the new version: $(head -c 400 "$tmp/diff")"
fi

# check_state LABEL: every file is the old or the new version, a temporary,
# or in the killed run's staging folder (fit/build_staging.h); and the
# outputs (all but cache/) are either all the old versions or, when the
# kill landed while they were being moved into place, partly new: counted
# in "mixed", which a kill seldom hits (the moves are a burst of renames).
check_state() {
  local label=$1 n_o=0 n_n=0 n_t=0 n_s=0 n_bad=0 n_missing=0 out_new=0 out_old=0 rel f
  while IFS= read -r -d '' f; do
    rel=${f#"$D/"}
    if [[ $rel =~ ^\.staging\.[0-9]+/ ]]; then
      n_s=$((n_s + 1))
    elif is_temp "$rel"; then
      n_t=$((n_t + 1))
      echo "     interrupted write: $rel ($(stat -c %s "$f") bytes)"
    elif [ -f "$tmp/start/$rel" ] && cmp -s "$f" "$tmp/start/$rel"; then
      n_o=$((n_o + 1))
      [[ $rel == cache/* ]] || { [ -f "$tmp/new/$rel" ] && cmp -s "$f" "$tmp/new/$rel"; } || out_old=$((out_old + 1))
    elif [ -f "$tmp/new/$rel" ] && cmp -s "$f" "$tmp/new/$rel"; then
      n_n=$((n_n + 1))
      [[ $rel == cache/* ]] || out_new=$((out_new + 1))
    else
      n_bad=$((n_bad + 1))
      echo "     $rel: $(stat -c %s "$f") bytes; old $(stat -c %s "$tmp/start/$rel" 2>/dev/null || echo -) bytes, new $(stat -c %s "$tmp/new/$rel" 2>/dev/null || echo -) bytes"
    fi
  done < <(find "$D" -type f -print0)
  while IFS= read -r -d '' f; do
    rel=${f#"$tmp/start/"}
    [ -e "$D/$rel" ] || { n_missing=$((n_missing + 1)); echo "     $rel: previous version vanished"; }
  done < <(find "$tmp/start" -type f -print0)
  state_temps=$n_t
  [ $out_new -gt 0 ] && [ $out_old -gt 0 ] && mixed=$((mixed + 1))
  if [ $n_bad -eq 0 ] && [ $n_missing -eq 0 ]; then
    pass "$label: $n_o old, $n_n new, $n_t temporaries, $n_s staged, 0 partial or unknown, 0 vanished; outputs $out_new new, $out_old old"
  else
    fail "$label: $n_bad partial or unknown files, $n_missing previous versions vanished ($n_o old, $n_n new, $n_t temporaries)"
  fi
}

# rerun_check LABEL: a rerun completes and leaves exactly the new version.
rerun_check() {
  if ! build "${new_args[@]}" >"$tmp/log" 2>&1; then
    fail "$1: rerun failed: $(head -c 300 "$tmp/log")"
  elif diff -r "$D" "$tmp/new" >"$tmp/diff"; then
    pass "$1: rerun completes, identical to the new version, no temporaries left"
  else
    fail "$1: rerun differs from the new version: $(head -c 400 "$tmp/diff")"
  fi
}

poll_temp() {   # a temporary exists somewhere in the output folder
  local t
  for t in "$D"/*.tmp.* "$D"/*/*.tmp.* "$D"/*/*/*.tmp.*; do return 0; done
  return 1
}

# kill_trial LABEL MODE DELAY_MS: one killed run from the start state.
kill_trial() {
  local label=$1 mode=$2 delay_ms=$3 rc
  rm -rf "$D"; cp -a "$tmp/start" "$D"
  # the binary itself in the background (not a shell function, whose
  # subshell would take the signal while skyfit went on writing)
  "$BIN" build "$tmp/scene.json" --out "$D" "${common[@]}" "${new_args[@]}" >"$tmp/log" 2>&1 &
  pid=$!
  sleep "$(awk -v m="$delay_ms" 'BEGIN { printf "%.3f", m / 1000 }')"
  if [ "$mode" = poll ]; then
    while kill -0 "$pid" 2>/dev/null && ! poll_temp; do :; done
  fi
  kill -9 "$pid" 2>/dev/null
  rc=0
  wait "$pid" 2>/dev/null || rc=$?
  pid=
  [ $rc -eq 0 ] && finished=$((finished + 1))
  [ $rc -eq 0 ] || [ $rc -eq 137 ] || fail "$label: exit $rc (want 137, SIGKILL, or 0 if it finished first)"
  check_state "$label ($mode, after $delay_ms ms of ~$run_ms, exit $rc)"
  [ "$state_temps" -gt 0 ] && mid_write=$((mid_write + 1))
}

mid_write=0 finished=0 mixed=0
for k in $(seq 1 "$trials"); do
  u=$(( (RANDOM * 32768 + RANDOM) % 1000 ))          # per mille of the run
  mode=delay; [ $((k % 2)) -eq 0 ] && mode=poll
  delay_ms=$(( run_ms * u / 1000 ))
  # polling kills start in the second half, where most files are written
  [ $mode = poll ] && delay_ms=$(( run_ms * (1000 + u) / 2000 ))
  kill_trial "kill $k" $mode $delay_ms
  if [ $((k % 4)) -eq 0 ]; then rerun_check "kill $k"; fi
done
# The delays follow the timed run; on a loaded machine (the sanitized suite
# beside other tests) later runs can be much faster, finish before every
# poll starts, and leave no write interrupted. Then polling kills from the
# start (up to 4) make sure a kill does land mid-write, checked as above.
extra=0
while [ "$mid_write" -eq 0 ] && [ $extra -lt 4 ]; do
  extra=$((extra + 1))
  kill_trial "extra kill $extra" poll 0
done
[ $extra -gt 0 ] && rerun_check "extra kills"
echo "$mid_write of $((trials + extra)) kills interrupted a write (a temporary was left); $finished runs finished before their kill"
[ "$mid_write" -ge 1 ] || fail "no kill landed during a write"
# SPEC §11: an interrupted run never touches the previous outputs. Only a
# kill during the final burst of renames leaves some new beside some old.
echo "$mixed of $((trials + extra)) kills left the outputs part old, part new (killed while moving them into place)"
[ "$mixed" -le 2 ] || fail "$mixed kills left the outputs part old, part new (want at most 2: the renames are a burst)"

# A publish that cannot complete moves nothing (fit/build_staging.h): a
# folder where one of the new run's pictures goes is found before the first
# move; the run exits 2 and every previous output stays as it was (a
# report.md made a folder had left metrics.json, report.html, views and
# weights replaced).
cp -a "$tmp/old" "$tmp/blocked"
cp -n "$tmp/new/cache/costs/"* "$tmp/blocked/cache/costs/"
picture=$(cd "$tmp/new/views" && ls | head -1)
rm -f "$tmp/blocked/views/$picture"
mkdir "$tmp/blocked/views/$picture"
"$BIN" build "$tmp/scene.json" --out "$tmp/blocked" "${common[@]}" "${new_args[@]}" >"$tmp/log" 2>&1
rc=$?
changed=0
while IFS= read -r -d '' f; do
  rel=${f#"$tmp/old/"}
  [ "$rel" = "views/$picture" ] && continue
  case $rel in cache/*) continue ;; esac
  cmp -s "$f" "$tmp/blocked/$rel" || changed=$((changed + 1))
done < <(find "$tmp/old" -type f -print0)
leftovers=$(find "$tmp/blocked" -name '.staging.*' -o -name '*.tmp.*' | wc -l)
echo "publish blocked by views/$picture/: exit $rc ($(tail -1 "$tmp/log")); $changed previous outputs changed, $leftovers leftovers"
[ $rc -eq 2 ] && [ $changed -eq 0 ] && [ "$leftovers" -eq 0 ] || fail "a blocked publish changed the previous outputs"

# Ctrl-C, SIGTERM (what timeout and CI send) and SIGHUP can be handled:
# the build then leaves neither its staging folder nor a temporary, the
# previous outputs untouched, and ends by that signal
# (cli/interrupt_cleanup.h). They had left .staging.PID/ and, in the
# cache, the table being written.
# Even trials wait for the staging folder to exist (the run is then past
# its tables), so that signals do land whatever the machine's speed.
landed=0
for k in 1 2 3 4 5 6; do
  sig=INT; [ $((k % 3)) -eq 1 ] && sig=TERM; [ $((k % 3)) -eq 2 ] && sig=HUP
  u=$(( (RANDOM * 32768 + RANDOM) % 1000 ))
  delay_ms=$(( run_ms * u / 1000 ))
  [ $((k % 2)) -eq 0 ] && delay_ms=0
  rm -rf "$D"; cp -a "$tmp/start" "$D"
  # (a background job ignores SIGINT unless told otherwise, as Ctrl-C's
  # foreground job does not)
  env --default-signal=INT "$BIN" build "$tmp/scene.json" --out "$D" "${common[@]}" "${new_args[@]}" >"$tmp/log" 2>&1 &
  pid=$!
  sleep "$(awk -v m="$delay_ms" 'BEGIN { printf "%.3f", m / 1000 }')"
  if [ $((k % 2)) -eq 0 ]; then
    while kill -0 "$pid" 2>/dev/null && [ -z "$(find "$D" -maxdepth 1 -name '.staging.*' -print -quit)" ]; do :; done
  fi
  kill -s $sig "$pid" 2>/dev/null
  rc=0
  wait "$pid" 2>/dev/null || rc=$?
  pid=
  want=$((128 + $(kill -l $sig)))
  [ $rc -eq $want ] && landed=$((landed + 1))
  [ $rc -eq 0 ] || [ $rc -eq $want ] || fail "SIG$sig after $delay_ms ms: exit $rc (want $want, or 0 if it finished first)"
  check_state "SIG$sig $k (after $delay_ms ms of ~$run_ms, exit $rc)"
  leftovers=$(find "$D" -name '.staging.*' -o -name '*.tmp.*' | wc -l)
  [ "$leftovers" -eq 0 ] || fail "SIG$sig $k: $leftovers staging folders or temporaries left: $(find "$D" -name '.staging.*' -o -name '*.tmp.*' | head -3)"
done
echo "$landed of 6 signals stopped a run (the others came after it had finished)"
[ "$landed" -ge 1 ] || fail "no signal stopped a run"
rerun_check "interrupts"

echo "$failures failed"
[ $failures -eq 0 ]
