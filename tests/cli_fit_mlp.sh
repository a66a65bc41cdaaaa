#!/usr/bin/env bash
# skyfit fit mlp-transmittance | mlp-scattering | mlp on small tables:
# byte-identical weights for 1 and 2 threads; an interrupted run (test hook
# and a real SIGINT) resumed with --resume ends byte-identical to a straight
# run; --dump-dataset / fit mlp round trip; bad input exits 2 writing nothing.
set -euo pipefail
BIN="${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
passed=0
failed=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
pass() { echo "ok    $*"; passed=$((passed + 1)); }
TAB=(--tables "$TMP/tables" --resolution 64x16,8x16x8x4 --orders 2)
TT=(--tables "$TMP/tables" --resolution 64x16,8x16x8x4)   # the transmittance network: no scattering orders

"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --polish 20 --threads 1 --out "$TMP/t1.json" --quiet
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --polish 20 --threads 2 --out "$TMP/t2.json" --quiet
if cmp -s "$TMP/t1.json" "$TMP/t2.json"; then pass "transmittance weights identical for 1 and 2 threads"; else fail "thread count changed the weights"; fi
# The transmittance network reads the transmittance table alone, makes no
# other, and refuses the scattering tables' options.
if "$BIN" fit mlp-transmittance "${TAB[@]}" --out "$TMP/orders.json" 2>"$TMP/orders.err"; then
  fail "fit mlp-transmittance took --orders"
elif grep -q -- "--orders: the transmittance network takes the transmittance table alone" "$TMP/orders.err" &&
  [ ! -e "$TMP/orders.json" ]; then pass "fit mlp-transmittance refuses --orders"
else fail "fit mlp-transmittance --orders: $(cat "$TMP/orders.err")"; fi
if [ -n "$(ls "$TMP/tables" | grep -v '^transmittance')" ]; then fail "fit mlp-transmittance made scattering tables: $(ls "$TMP/tables")"
else pass "fit mlp-transmittance made the transmittance table only"; fi
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --threads 1 --out "$TMP/s1.json" --quiet
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --threads 2 --out "$TMP/s2.json" --quiet
if cmp -s "$TMP/s1.json" "$TMP/s2.json"; then pass "scattering weights identical for 1 and 2 threads"; else fail "thread count changed the scattering weights"; fi
# --normalise brightness (fit/output_norm.h, the default; above): the sky
# network's coefficients and cap in the file, the ground network's targets
# raw; without the cap, coefficients only; --normalise none, neither
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --threads 1 --normalise none --out "$TMP/n1.json" --quiet
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --threads 1 --normalise-cap none --out "$TMP/nc.json" --quiet
grep -q '"norm_coef"' "$TMP/s1.json" && grep -q '"norm_cap"' "$TMP/s1.json" && ! grep -q '"ground_norm_coef"' "$TMP/s1.json" &&
  grep -q '"normalise":[[:space:]]*"brightness"' "$TMP/s1.json" && ! grep -q '"norm_coef"' "$TMP/n1.json" &&
  grep -q '"normalise":[[:space:]]*"none"' "$TMP/n1.json" && grep -q '"norm_coef"' "$TMP/nc.json" &&
  ! grep -q '"norm_cap"' "$TMP/nc.json" &&
  pass "brightness by default: the sky network's norm_coef and norm_cap in the file; no cap with --normalise-cap none; neither with --normalise none" ||
  fail "normalisation: norm_coef / norm_cap missing or misplaced"
# each network's losses apart, in the units of its targets (fit/train_losses_json.h)
/usr/bin/python3 - "$TMP/s1.json" "$TMP/n1.json" <<'PY' &&
import json, math, sys
for path, sky_units in ((sys.argv[1], "brightness_normalised"), (sys.argv[2], "raw")):
    m = json.load(open(path))["metrics"]
    g = m["ground_network"]
    assert m["loss_targets"] == sky_units and g["loss_targets"] == "raw", (path, m)
    assert all(math.isfinite(x[k]) and x[k] > 0 for x in (m, g) for k in ("train_loss", "validation_loss")), m
PY
  pass "losses per network: the sky network's in its targets' units, the ground network's raw" ||
  fail "losses per network: missing, or units misnamed"
# interrupted in the normalised sky network, resumed: the normalisation is
# fitted again from the same data, to the straight run's bytes
set +e
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --threads 1 --out "$TMP/nr.json" \
  --stop-after-epochs 2 --quiet
rc=$?
set -e
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --threads 1 --out "$TMP/nr.json" \
  --resume --quiet
[ "$rc" = 130 ] && cmp -s "$TMP/nr.json" "$TMP/s1.json" &&
  pass "normalised, interrupted after 2 epochs and resumed: identical to the straight run" ||
  fail "normalised resume: rc $rc, or the weights differ"

# the scattering model split at the horizon (models/mlp_sky.h): two networks
# in one file; the hook interrupting the second (3 epochs each, the hook at
# 5 of the command's epochs: the first network's finished state is kept
# beside the second's checkpoint), then the first; each resumed to the
# straight run
grep -q '"ground_W0"' "$TMP/s1.json" && grep -q '"split":[[:space:]]*"horizon"' "$TMP/s1.json" &&
  pass "scattering weights hold the ground-ray network (split horizon)" || fail "no ground-ray network in the weights"
# --scene restricts the data to its domain; viewers on the ground looking
# everywhere: every ray to the ground has length 0 (the model's exact 0), so
# no ground-ray network is trained (the sky half alone has 2048 rays here,
# enough to split)
printf '{"name": "on-ground", "viewer_altitude_km": [0, 0], "view": "all", "sun_elevation_deg": [0, 90], "quantities": ["sky_radiance"], "color": "rgb"}\n' >"$TMP/ground.json"
"$BIN" fit mlp-scattering --tables "$TMP/tables-g" --resolution 64x16,8x64x16x4 --orders 2 --scene "$TMP/ground.json" \
  --epochs 1 --batch 256 --polish 1 --dump-dataset "$TMP/sg.csv" --out "$TMP/sg.json" 2>"$TMP/sg.err"
# that table is too coarse for the brightness's 28 coefficients: raw
# targets, and the command says so
grep -q "training the sky network on raw targets: brightness normalisation: .* for 28 coefficients" "$TMP/sg.err" &&
  grep -q '"normalise":[[:space:]]*"none"' "$TMP/sg.json" &&
  pass "a table too coarse for the brightness: raw targets, with a note" ||
  fail "coarse table: no fallback note ($(cat "$TMP/sg.err")) or the file says normalised"
h_values=$(tail -n +2 "$TMP/sg.csv" | cut -d, -f1 | sort -u | wc -l)
mu_range=$(tail -n +2 "$TMP/sg.csv" | cut -d, -f2 | sort -g | sed -n '1p;$p' | tr '\n' ' ')
[ "$h_values" = 1 ] && [ "$mu_range" = "-1 1 " ] && pass "--scene: the data are the domain's rays, from h = 0 in every direction" ||
  fail "--scene: rows at $h_values altitudes (want 1), mu from $mu_range(want -1 1)"
! grep -q '"ground_W0"' "$TMP/sg.json" && pass "viewers on the ground: one network (rays to the ground all of length 0)" ||
  fail "viewers on the ground: a ground-ray network was trained on rays of length 0"
for stop in 5 2; do
  set +e
  "$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --out "$TMP/sr.json" --stop-after-epochs $stop --quiet
  rc=$?
  set -e
  sky="$TMP/sr.json.checkpoint" ground="$TMP/sr.json.checkpoint.ground"
  [ "$rc" = 130 ] && [ -f "$sky" ] && if [ $stop = 5 ]; then [ -f "$ground" ]; else [ ! -f "$ground" ]; fi &&
    [ ! -f "$TMP/sr.json" ] && pass "split, hook after $stop epochs: exit 130, checkpoints $(cd "$TMP" && echo sr.json.ch*)" ||
    fail "split interrupt after $stop: rc $rc, $(cd "$TMP" && echo sr.json*)"
  "$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --out "$TMP/sr.json" --resume --quiet
  cmp -s "$TMP/sr.json" "$TMP/s1.json" && [ ! -f "$sky" ] && [ ! -f "$ground" ] &&
    pass "split, resumed after $stop epochs: identical to the straight run, checkpoints removed" || fail "split resume after $stop differs"
  rm -f "$TMP/sr.json"
done
# interrupted in a polish (the hook after 2 of 3 steps: the first network's;
# after 5 of 20, the transmittance network's): exit 130, no weights, the
# trained state kept; --resume polishes again to the straight run
set +e
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --out "$TMP/sp.json" --stop-after-polish-steps 2 \
  --quiet 2>"$TMP/sp.err"
rc_s=$?
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --polish 20 --threads 1 --out "$TMP/tp.json" \
  --stop-after-polish-steps 5 --quiet 2>"$TMP/tp.err"
rc_t=$?
set -e
[ "$rc_s" = 130 ] && [ "$rc_t" = 130 ] && [ -f "$TMP/sp.json.checkpoint" ] && [ ! -f "$TMP/sp.json.checkpoint.ground" ] &&
  [ -f "$TMP/tp.json.checkpoint" ] && [ ! -e "$TMP/sp.json" ] && [ ! -e "$TMP/tp.json" ] &&
  grep -q "interrupted in the polish after 2 of 3 steps" "$TMP/sp.err" &&
  grep -q "interrupted in the polish after 5 of 20 steps" "$TMP/tp.err" &&
  pass "polish interrupted: exit 130, trained states kept, no weights" ||
  fail "polish interrupted: rc $rc_s $rc_t, $(cat "$TMP/sp.err" "$TMP/tp.err")"
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --out "$TMP/sp.json" --resume --quiet
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --polish 20 --threads 1 --out "$TMP/tp.json" --resume --quiet
cmp -s "$TMP/sp.json" "$TMP/s1.json" && cmp -s "$TMP/tp.json" "$TMP/t1.json" && [ ! -e "$TMP/sp.json.checkpoint" ] &&
  [ ! -e "$TMP/tp.json.checkpoint" ] && pass "polish interrupted, resumed: identical to the straight runs, checkpoints removed" ||
  fail "polish resume differs or left a checkpoint"

"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 3 --batch 64 --polish 3 --split none --out "$TMP/s0.json" --quiet
! grep -q '"ground_W0"' "$TMP/s0.json" && grep -q '"split":[[:space:]]*"none"' "$TMP/s0.json" &&
  pass "--split none: one network" || fail "--split none still wrote a ground-ray network"

# interruption by the test hook, twice, then --resume
set +e
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --restarts 2 --patience 5 --polish 10 --out "$TMP/r.json" --stop-after-epochs 7 --quiet
rc=$?
set -e
[ "$rc" = 130 ] && [ -f "$TMP/r.json.checkpoint" ] && [ ! -f "$TMP/r.json" ] && pass "interrupted: exit 130, checkpoint, no weights" || fail "interrupt: rc $rc"
# A damaged checkpoint (8 bytes overwritten with a NaN's, at its epoch
# counters, its losses and its parameters; one byte appended) is refused,
# exit 2, nothing written, the checkpoint kept: it had resumed into 2
# billion epochs, a false "diverged" or other weights, each silently.
for damage in 40 60 100 200 append; do
  cp "$TMP/r.json.checkpoint" "$TMP/damaged.checkpoint"
  if [ "$damage" = append ]; then printf 'x' >>"$TMP/damaged.checkpoint"
  else printf '\x00\x00\x00\x00\x00\x00\xf8\x7f' | dd of="$TMP/damaged.checkpoint" bs=1 seek="$damage" conv=notrunc status=none; fi
  set +e
  err=$("$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --restarts 2 --patience 5 --polish 10 --out "$TMP/damaged.json" \
    --checkpoint "$TMP/damaged.checkpoint" --resume --quiet 2>&1)
  rc=$?
  set -e
  [ "$rc" = 2 ] && echo "$err" | grep -q "damaged.checkpoint: checkpoint is corrupt" && [ ! -e "$TMP/damaged.json" ] &&
    [ -f "$TMP/damaged.checkpoint" ] && pass "checkpoint damaged ($damage): exit 2, $err" || fail "checkpoint damaged ($damage): rc $rc, '$err'"
done
set +e
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --restarts 2 --patience 5 --polish 10 --out "$TMP/r.json" --resume --stop-after-epochs 20 --quiet
set -e
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --restarts 2 --patience 5 --polish 10 --out "$TMP/r.json" --resume --quiet
"$BIN" fit mlp-transmittance "${TT[@]}" --epochs 30 --restarts 2 --patience 5 --polish 10 --out "$TMP/straight.json" --quiet
if cmp -s "$TMP/r.json" "$TMP/straight.json"; then pass "resumed run identical to the straight run"; else fail "resume differs"; fi
[ ! -f "$TMP/r.json.checkpoint" ] && pass "checkpoint removed after the finished run" || fail "checkpoint left behind"

# dataset dump and fit mlp on it; a real SIGINT and --resume
"$BIN" fit mlp-transmittance "${TT[@]}" --dump-dataset "$TMP/t.csv" --quiet
rows=$(($(wc -l <"$TMP/t.csv") - 1))
header=$(head -1 "$TMP/t.csv")
[ "$header" = "x_r,x_mu,T_r,T_g,T_b" ] && [ "$rows" -gt 500 ] && pass "dump: $rows rows, header $header" || fail "dump: $rows rows, header $header"
json=$("$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 200 --batch 64 --quiet)
mse=$(echo "$json" | sed 's/.*"final_train_mse": \([^,]*\),.*/\1/')
awk -v m="$mse" 'BEGIN { exit !(m > 0 && m < 0.03) }' && pass "fit mlp prints final_train_mse $mse" || fail "fit mlp: $json"
# Its figures are its output: a full disk had lost them with exit 0.
if [ -w /dev/full ]; then
  set +e
  err=$("$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 2 --batch 64 --quiet 2>&1 >/dev/full)
  rc=$?
  set -e
  [ "$rc" = 1 ] && echo "$err" | grep -q "writing to stdout failed" && pass "fit mlp, stdout on a full disk: exit 1, $err" ||
    fail "fit mlp, stdout on a full disk: rc $rc, '$err'"
fi
# More restarts never keep a worse network: without a validation set the
# kept network is the restart's whose last network has the lowest loss
# over the whole training set (the last epoch's mean of the batches'
# losses, each before its step, had kept the worse restart: seeds 3 and 14
# of these 24). Restart 0 is the same run in each.
awk 'BEGIN { srand(7); print "x0,x1,x2,y0,y1";
  for (i = 0; i < 700; ++i) { a = rand(); b = rand(); c = rand();
    printf "%.17g,%.17g,%.17g,%.17g,%.17g\n", a, b, c, 0.5 * (a * b + c * c * c), 0.5 + 0.4 * sin(3 * a - 2 * b + c) }}' \
  >"$TMP/restarts.csv"
worse=""
for seed in $(seq 1 24); do
  l1=$("$BIN" fit mlp --data "$TMP/restarts.csv" --inputs 3 --layers 3,6,5,2 --epochs 4 --lr 0.1 --seed "$seed" \
    --batch 128 --restarts 1 --quiet | sed 's/.*"final_train_loss": \([^,]*\),.*/\1/')
  l2=$("$BIN" fit mlp --data "$TMP/restarts.csv" --inputs 3 --layers 3,6,5,2 --epochs 4 --lr 0.1 --seed "$seed" \
    --batch 128 --restarts 2 --quiet | sed 's/.*"final_train_loss": \([^,]*\),.*/\1/')
  awk -v a="$l1" -v b="$l2" 'BEGIN { exit !(b <= a) }' || worse="$worse seed $seed: $l1 -> $l2;"
done
[ -z "$worse" ] && pass "restarts 2 keep a network no worse than restart 1 (24 seeds)" || fail "a second restart kept a worse network:$worse"
# Targets whose MSE overflows (1e200) train on the log loss: the weights are
# written without the metric and stdout says null (the file had been
# refused and the network lost; stdout had printed inf).
awk 'BEGIN { srand(3); print "x0,x1,y0,y1"; for (i = 0; i < 300; ++i) { a = rand(); b = rand();
  printf "%.17g,%.17g,%.17g,%.17g\n", a, b, 1e200 * exp(a), 1e-200 * exp(b) }}' >"$TMP/huge.csv"
set +e
json=$("$BIN" fit mlp --data "$TMP/huge.csv" --inputs 2 --layers 2,4,2 --epochs 5 --loss log --out "$TMP/huge.json" 2>&1)
rc=$?
set -e
[ "$rc" = 0 ] && [ -s "$TMP/huge.json" ] && echo "$json" | python3 -c "import json, sys; d = json.load(sys.stdin); assert d['final_train_mse'] is None and d['final_train_loss'] > 0" &&
  pass "targets of 1e200: weights written, final_train_mse null" || fail "targets of 1e200: rc $rc, $json"
plain=$("$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 50 --batch 64 --quiet)
polished=$("$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 50 --batch 64 --polish 20 --quiet)
m0=$(echo "$plain" | sed 's/.*"final_train_mse": \([^,]*\),.*/\1/')
m1=$(echo "$polished" | sed 's/.*"final_train_mse": \([^,]*\),.*/\1/')
awk -v a="$m0" -v b="$m1" 'BEGIN { exit !(b > 0 && b < 0.8 * a) }' && pass "polish: training MSE $m0 -> $m1" || fail "polish: $m0 -> $m1"
# --target-root 4 (fit/target_root.h): the dump holds the targets' fourth
# roots; fit mlp trains the same network on it, and the weights file holds
# that network turned into T's: the output biases less ln 4, every other
# parameter the same bits; its validation figures in transmittance
"$BIN" fit mlp-transmittance "${TT[@]}" --target-root 4 --epochs 30 --polish 20 --threads 1 \
  --dump-dataset "$TMP/t4.csv" --out "$TMP/t4.json" --quiet
"$BIN" fit mlp --data "$TMP/t4.csv" --inputs 2 --layers 2,16,16,3 --output exp_neg_exp --epochs 30 --batch 256 \
  --lr-decay 0.995 --polish 20 --validation 0.1 --seed 1 --threads 1 --out "$TMP/t4_csv.json" --quiet >/dev/null
/usr/bin/python3 - "$TMP" <<'PY' && pass "--target-root 4: fourth roots dumped, the same network trained on them, its output biases less ln 4" ||
import csv, json, math, sys
t = sys.argv[1]
raw = list(csv.reader(open(f"{t}/t.csv")))[1:]
roots = list(csv.reader(open(f"{t}/t4.csv")))[1:]
assert len(raw) == len(roots)
for a, b in zip(raw, roots):
    assert a[:2] == b[:2]
    for y, r in zip(a[2:], b[2:]):
        assert abs(float(r) - float(y) ** 0.25) <= 1e-15 * max(1.0, float(y) ** 0.25), (y, r)
w4, wc, w1 = (json.load(open(f"{t}/{n}.json")) for n in ("t4", "t4_csv", "t1"))
assert w4["training"]["target_root"] == 4 and w4["metrics"]["loss_targets"] == "root_4", w4["training"]
assert "target_root" not in w1["training"] and w1["metrics"]["loss_targets"] == "raw"
p4, pc = w4["params"], wc["params"]
last = "b%d" % (len([k for k in p4 if k.startswith("W")]) - 1)
for k in pc:
    if k == last:
        assert all(abs(a - (b - math.log(4))) <= 1e-15 for a, b in zip(p4[k], pc[k])), (p4[k], pc[k])
    else:
        assert p4[k] == pc[k], k
# the same held-out samples, measured in transmittance (not in its fourth
# roots, whose mean is higher): the reference's mean as the plain run's
v4, v1 = w4["metrics"]["validation"], w1["metrics"]["validation"]
assert v4["points"] == v1["points"] and abs(v4["mean_reference"] - v1["mean_reference"]) <= 1e-12, (v4, v1)
print("target root 4: validation RMSE %.3g (plain %.3g); full rays max abs %.3g (plain %.3g)" % (
    v4["rmse_all"], v1["rmse_all"], w4["metrics"]["full_ray_random"]["max_abs_all"], w1["metrics"]["full_ray_random"]["max_abs_all"]))
PY
  fail "--target-root 4: dump, conversion or metrics wrong"
# what the terminal shows: a validation loss only with a validation set
# (fit mlp has none unless asked); the progress line needs a terminal
# (script(1), where installed)
for v in 0 0.1; do
  said=$("$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 5 --batch 64 --polish 3 --validation $v \
    2>&1 >/dev/null)
  if command -v script >/dev/null; then
    said="$said $(script -qec "'$BIN' fit mlp --data '$TMP/t.csv' --inputs 2 --layers 2,4,3 --epochs 5 --batch 64 \
      --validation $v" /dev/null 2>&1 | tr '\r' '\n' | grep ' epoch ')"
  fi
  case "$v:$said" in
    0:*validation* | 0:*nan* | 0.1:*nan*) fail "terminal output, --validation $v: $said" ;;
    0:*polish:*) pass "terminal output without a validation set: no validation loss" ;;
    0.1:*polish:*validation*epoch*validation*) pass "terminal output with --validation 0.1: its loss" ;;
    0.1:*polish:*validation*) command -v script >/dev/null && fail "no progress line: $said" ||
      pass "terminal output with --validation 0.1: its loss (polish line; no script(1))" ;;
    *) fail "terminal output, --validation $v: $said" ;;
  esac
done
# 10,000 epochs: about 1.3 s on a 2-core EPYC, so that the signal half a
# second in lands in training (3,000 finished before it there). SIGTERM
# and SIGHUP checkpoint as SIGINT does (they had ended the run with nothing
# kept). A background job ignores SIGINT, hence env; the signal goes to the
# command, which passes it to its work process (cli/interrupt_cleanup.h).
"$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,8,3 --epochs 10000 --batch 16 --out "$TMP/m_straight.json" --quiet >/dev/null
for sig in INT TERM; do
  rm -f "$TMP/m.json" "$TMP/m.json.checkpoint"
  env --default-signal=INT "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,8,3 --epochs 10000 --batch 16 \
    --out "$TMP/m.json" --quiet >/dev/null &
  pid=$!
  sleep 0.5
  kill -$sig "$pid" 2>/dev/null || true
  set +e
  wait "$pid"
  rc=$?
  set -e
  if [ "$rc" = 130 ]; then
    [ -f "$TMP/m.json.checkpoint" ] && pass "SIG$sig: exit 130 and a checkpoint" || fail "SIG$sig: no checkpoint"
    "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,8,3 --epochs 10000 --batch 16 --out "$TMP/m.json" --resume --quiet >/dev/null
  else
    echo "note: the run finished before SIG$sig arrived (rc $rc)"
  fi
  if cmp -s "$TMP/m.json" "$TMP/m_straight.json"; then pass "SIG$sig + --resume identical to the straight run"; else fail "SIG$sig resume differs"; fi
  left=$(find "$TMP" -maxdepth 1 -name 'm.json*.tmp.*' | wc -l)
  [ "$left" -eq 0 ] && pass "SIG$sig: no temporary left" || fail "SIG$sig: $left temporaries left"
done
# A resume whose training had finished (interrupted in the polish) runs no
# epoch: its time per epoch is null, not 0
rc=0
"$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 20 --batch 64 --polish 3 \
  --stop-after-polish-steps 1 --out "$TMP/fin.json" --quiet >/dev/null 2>&1 || rc=$?
json=$("$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --epochs 20 --batch 64 --polish 3 \
  --out "$TMP/fin.json" --resume --quiet)
case "$json" in
  *'"seconds_per_epoch": null, "cpu_seconds_per_epoch": null, "epochs": 20, "epochs_this_run": 0,'*)
    [ "$rc" = 130 ] && pass "resumed after the training finished: seconds_per_epoch null, 0 epochs this run" ||
      fail "finished-training hook: rc $rc" ;;
  *) fail "resumed after the training finished (rc $rc): $json" ;;
esac
case "$(echo "$plain" | sed 's/.*"epochs_this_run": \([0-9]*\),.*/\1/')" in
  50) pass "a straight run reports its 50 epochs this run" ;;
  *) fail "epochs_this_run of a straight run: $plain" ;;
esac

# Bruneton's horizon-aware inputs (models/mlp_sky.h): stored as the input
# names and emitted in C and GLSL. The emitted C header, compiled, evaluates
# full rays (eq. 43) within the trained accuracy of the exact optical depth
# (skyfit eval), which a wrong mapping in the emitter would miss by far; the
# GLSL compiles. (test_mlp_input_map: float vs double, file round trip.)
metric() { /usr/bin/python3 -c 'import json, sys; m = json.load(open(sys.argv[1]))["metrics"]; print(eval(sys.argv[2]))' "$@"; }
"$BIN" fit mlp-transmittance "${TT[@]}" --input-map bruneton --layers 2,8,8,3 --epochs 100 --polish 300 \
  --out "$TMP/tb.json" --quiet
grep -q '"name":[[:space:]]*"x_r"' "$TMP/tb.json" && grep -q '"name":[[:space:]]*"x_mu"' "$TMP/tb.json" &&
  pass "weights file names the inputs x_r, x_mu" || fail "input names x_r, x_mu missing"
rb=$(metric "$TMP/tb.json" 'm["rmse"]')
ray=$(metric "$TMP/tb.json" 'm["full_ray_random"]["rmse_all"]')
# measured 2.5e-3 held-out and 4.6e-3 on random full rays (the seed's 2-4-3
# with Adam alone: 0.24 and 0.13 on this problem)
awk -v b="$rb" -v r="$ray" 'BEGIN { exit !(b > 0 && b < 4e-3 && r < 8e-3) }' &&
  pass "x_r, x_mu 2-8-8-3, 100 epochs + 300 LM steps: held-out RMSE $rb < 4e-3, full rays $ray < 8e-3" ||
  fail "x_r, x_mu held-out RMSE $rb, full rays $ray"
mkdir -p "$TMP/gen"
"$BIN" codegen --weights "$TMP/tb.json" --lang both --out "$TMP/gen" >/dev/null 2>&1
grep -q "x_mu" "$TMP/gen/skyfit.h" && grep -q "x_mu" "$TMP/gen/skyfit.glsl" &&
  pass "C and GLSL both evaluate x_r, x_mu" || fail "mapping not emitted"
{ echo "h_km,mu"; awk 'BEGIN { srand(3); for (i = 0; i < 400; ++i) { q = 10 * rand(); printf "%.9g,%.9g\n", q * q, 2 * rand() - 1 } }'; } >"$TMP/pts.csv"
"$BIN" eval transmittance <"$TMP/pts.csv" >"$TMP/ref.csv"
cat >"$TMP/drive.c" <<'CEOF'
#include <stdio.h>
#include "skyfit.h"
int main(void) {
  char line[256];
  double h, mu;
  if (!fgets(line, sizeof line, stdin)) return 1;
  while (scanf("%lf,%lf", &h, &mu) == 2) {
    skyfit_vec3 t = skyfit_mlp_transmittance((float)h, (float)mu);
    printf("%.9g,%.9g,%.9g\n", t.x, t.y, t.z);
  }
  return 0;
}
CEOF
if cc -std=c99 -O2 -Wall -Wextra -Werror -pedantic -I"$TMP/gen" -o "$TMP/drive" "$TMP/drive.c" -lm; then
  "$TMP/drive" <"$TMP/pts.csv" >"$TMP/gen.csv"
  rc_=$(paste -d, "$TMP/gen.csv" <(tail -n +2 "$TMP/ref.csv") |
    awk -F, '{ for (c = 0; c < 3; ++c) { d = $(1 + c) - $(NF - 2 + c); s += d * d; m++ } } END { printf "%.3g", sqrt(s / m) }')
  awk -v e="$rc_" -v r="$ray" 'BEGIN { exit !(e < 2 * r + 2e-3) }' &&
    pass "emitted C (x_r, x_mu), 400 full rays vs exact: RMSE $rc_ (model's own: $ray)" || fail "emitted C full-ray RMSE $rc_ (model $ray)"
else
  fail "the emitted C header does not compile"
fi
if command -v glslangValidator >/dev/null; then
  { printf '#version 450\nlayout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer B { vec4 v[]; };\n'
    grep -v '^#version' "$TMP/gen/skyfit.glsl"
    printf 'void main() { v[0] = vec4(skyfit_mlp_transmittance(v[1].x, v[1].y), 0.0); }\n'; } >"$TMP/t.comp"
  glslangValidator "$TMP/t.comp" >"$TMP/glslang.log" 2>&1 && pass "glslangValidator: the x_r, x_mu GLSL compiles" ||
    { cat "$TMP/glslang.log"; fail "glslangValidator rejected the x_r, x_mu GLSL"; }
else
  fail "glslangValidator is not installed (scripts/setup.sh installs it)"
fi

# A sky network whose output can go negative (linear) is held at 0, in the
# double evaluator (eval --model) and in the emitted float32 C (they had
# given L = -0.0196 near the ground looking down, sun below the horizon).
"$BIN" fit mlp-scattering "${TAB[@]}" --epochs 1 --batch 64 --polish 0 --output linear --hidden relu \
  --out "$TMP/lin.json" --quiet
mkdir -p "$TMP/lin" && "$BIN" codegen --weights "$TMP/lin.json" --lang c --name lin --out "$TMP/lin" >/dev/null
python3 - "$TMP/pts.csv" <<'PY'
import itertools, sys
with open(sys.argv[1], "w") as f:
    f.write("h_km,mu,mu_s,nu\n")
    for h, mu, ms in itertools.product([1e-6, 0.5, 5, 40, 99.9], [-1, -0.5, -0.05, 0, 0.05, 0.5, 1], [-0.5, -0.1, 0, 0.1, 0.6, 1]):
        for nu in (-1, 0, 1):
            f.write(f"{h},{mu},{ms},{nu}\n")
PY
"$BIN" eval sky_radiance --model "$TMP/lin.json" <"$TMP/pts.csv" >"$TMP/lin-eval.csv" 2>/dev/null
neg=$(awk -F, 'NR > 1 && ($5 < 0 || $6 < 0 || $7 < 0)' "$TMP/lin-eval.csv" | wc -l)
[ "$neg" = 0 ] && [ "$(wc -l <"$TMP/lin-eval.csv")" -gt 600 ] && pass "linear sky network: no negative radiance in double" ||
  fail "linear sky network: $neg negative radiances in double"
cat >"$TMP/lin-main.c" <<'C'
#include <stdio.h>
#include "lin.h"
int main(void) {
  float h, mu, ms, nu;
  int bad = 0, n = 0;
  char line[256];
  fgets(line, sizeof line, stdin);
  while (scanf("%f,%f,%f,%f", &h, &mu, &ms, &nu) == 4) {
    skyfit_vec3 l = skyfit_mlp_sky_radiance(h, mu, ms, nu);
    bad += !(l.x >= 0.0f && l.y >= 0.0f && l.z >= 0.0f);
    ++n;
  }
  printf("%d of %d\n", bad, n);
  return bad != 0;
}
C
out=
cc -std=c99 -O2 -I"$TMP/lin" "$TMP/lin-main.c" -o "$TMP/lin-main" -lm && out=$("$TMP/lin-main" <"$TMP/pts.csv") &&
  pass "linear sky network: no negative radiance in the emitted float32 C ($out)" ||
  fail "linear sky network: negative radiance in the emitted float32 C ($out)"

# bad input: exit 2, message, nothing written
expect_error() {
  local name=$1 pattern=$2
  shift 2
  set +e
  err=$("$@" 2>&1 >/dev/null)
  rc=$?
  set -e
  if [ "$rc" = 2 ] && echo "$err" | grep -q -- "$pattern" && [ ! -e "$TMP/bad.json" ]; then pass "$name: $err"; else fail "$name: rc $rc, '$err'"; fi
}
expect_error "bad layers" "--layers" "$BIN" fit mlp-transmittance --layers 2,x,3 --out "$TMP/bad.json"
expect_error "--inputs past the columns the data can hold" "expected a whole number in 1..63 (the data hold at most 64 columns), got '64'" \
  "$BIN" fit mlp --data "$TMP/t.csv" --inputs 64 --layers 64,2 --out "$TMP/bad.json"
printf 'x,y\n0,0\n1,1\n0.5,0.5\n0.2,0.3\n' >"$TMP/four.csv"
expect_error "--patience with a validation fraction that rounds to no rows" \
  "--patience 2: early stopping watches the validation loss, and the validation set is empty" \
  "$BIN" fit mlp --data "$TMP/four.csv" --inputs 1 --layers 1,2,1 --epochs 3 --validation 0.1 --patience 2 --out "$TMP/bad.json"
# the mse loss on them is refused before training (it had "diverged", exit 1, "try a smaller --lr")
expect_error "mse on targets of 1e200" "target column 'y0' reaches 2.7[0-9]e+200: its squared errors overflow" \
  "$BIN" fit mlp --data "$TMP/huge.csv" --inputs 2 --layers 2,4,2 --epochs 5 --out "$TMP/bad.json"
expect_error "bad polish" "--polish" "$BIN" fit mlp-transmittance --polish -3 --out "$TMP/bad.json"
expect_error "bad input map" "--input-map" "$BIN" fit mlp-transmittance --input-map polar --out "$TMP/bad.json"
expect_error "bad loss" "--loss" "$BIN" fit mlp-scattering --loss huber --out "$TMP/bad.json"
expect_error "bad target root" "--target-root: expected an integer in 1..16" "$BIN" fit mlp-transmittance --target-root 0 \
  --out "$TMP/bad.json"
expect_error "target root of a sigmoid output" "needs the output exp_neg or exp_neg_exp" "$BIN" fit mlp-transmittance \
  --target-root 4 --output sigmoid --out "$TMP/bad.json"
expect_error "leenman tables" "--parameterization: the networks train on the tables of the bruneton" "$BIN" fit mlp-scattering \
  --parameterization leenman --out "$TMP/bad.json"
expect_error "bad split" "--split" "$BIN" fit mlp-scattering --split vertical --out "$TMP/bad.json"
expect_error "bad normalisation" "--normalise" "$BIN" fit mlp-scattering --normalise log --out "$TMP/bad.json"
expect_error "negative normalisation cap" "--normalise-cap" "$BIN" fit mlp-scattering --normalise-cap -1 --out "$TMP/bad.json"
# 100 channels, two constituents that scatter: 300 outputs of the separate
# target, more than a layer may have (the shape's error had been ignored)
python3 -c "
import json
c = lambda n, s, p: {'name': n, 'scattering': s, 'absorption': 0, 'phase': p, 'density': [{'exp_term': 1, 'exp_scale_per_km': -0.125}]}
print(json.dumps({'name': 'wide', 'bottom_radius_km': 6360, 'top_radius_km': 6460,
                  'channels': {'wavelengths_nm': [400 + 3 * i for i in range(100)]},
                  'constituents': [c('rayleigh', {'recipe': 'rayleigh_bucholtz'}, {'kind': 'rayleigh'}),
                                   c('haze', [1e-3] * 100, {'kind': 'henyey_greenstein', 'g': 0.7})]}))" >"$TMP/a100.json"
expect_error "300 outputs" "the network would have 300 outputs (100 channels times" "$BIN" fit mlp-scattering \
  --atmosphere "$TMP/a100.json" --out "$TMP/bad.json"
expect_error "layers vs data" "inputs and" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 3,4,3 --out "$TMP/bad.json"
printf 'a,b,c\n1,2,3\n1,oops,3\n' >"$TMP/bad.csv"
expect_error "bad csv" "line 3, column 2" "$BIN" fit mlp --data "$TMP/bad.csv" --inputs 2 --layers 2,2,1 --out "$TMP/bad.json"
expect_error "missing resume" "checkpoint" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 --resume --out "$TMP/bad.json"
expect_error "resume without a checkpoint path" "needs --out or --checkpoint" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 \
  --layers 2,4,3 --resume
# from the audit: each had run the whole training first, or destroyed a file
cp "$TMP/t.csv" "$TMP/t-copy.csv"
expect_error "checkpoint is the data" "the same file as another of the run's files" "$BIN" fit mlp --data "$TMP/t-copy.csv" \
  --inputs 2 --layers 2,4,3 --checkpoint "$TMP/t-copy.csv" --out "$TMP/bad.json"
cmp -s "$TMP/t.csv" "$TMP/t-copy.csv" && pass "checkpoint is the data: the data untouched" || fail "the data were overwritten"
expect_error "checkpoint is --out" "the same file as --out" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 \
  --checkpoint "$TMP/bad.json" --out "$TMP/bad.json"
expect_error "--out in a missing folder" "cannot write here" "$BIN" fit mlp-transmittance "${TT[@]}" \
  --out "$TMP/no-such-folder/w.json"
expect_error "--patience without validation" "give --validation" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 \
  --layers 2,4,3 --patience 3 --out "$TMP/bad.json"
expect_error "a polish beyond memory" "normal equations" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 \
  --layers 2,256,256,256,3 --polish 1 --out "$TMP/bad.json"
expect_error "--threads beyond 256" "--threads" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 \
  --threads 10000 --out "$TMP/bad.json"
expect_error "--seed beyond 2^53" "--seed" "$BIN" fit mlp --data "$TMP/t.csv" --inputs 2 --layers 2,4,3 \
  --seed 9007199254740993 --out "$TMP/bad.json"
# targets the loss cannot measure: exit 2 naming the column (they had ended
# as "training diverged in every restart", exit 1)
awk -F, 'BEGIN { OFS = "," } NR == 1 { print; next } { $3 = -$3; print }' "$TMP/t.csv" >"$TMP/neg.csv"
awk -F, 'BEGIN { OFS = "," } NR == 1 { print; next } { $4 = 0; print }' "$TMP/t.csv" >"$TMP/zero.csv"
col3=$(head -1 "$TMP/t.csv" | cut -d, -f3) col4=$(head -1 "$TMP/t.csv" | cut -d, -f4)
expect_error "log loss of negative targets" "target column '$col3'" "$BIN" fit mlp --data "$TMP/neg.csv" --inputs 2 \
  --layers 2,4,3 --loss log --output linear --out "$TMP/bad.json"
expect_error "rel loss of a zero column" "target column '$col4' is 0 throughout" "$BIN" fit mlp --data "$TMP/zero.csv" \
  --inputs 2 --layers 2,4,3 --loss rel --out "$TMP/bad.json"
# --resume without a checkpoint fails before the tables are sampled: the
# empty tables folder stays empty
for q in transmittance scattering; do
  mkdir -p "$TMP/no-tables-$q"
  expect_error "$q: missing resume" "no checkpoint to resume from" "$BIN" fit mlp-$q --tables "$TMP/no-tables-$q" \
    --resume --out "$TMP/bad.json"
  [ -z "$(ls -A "$TMP/no-tables-$q")" ] && pass "$q: missing resume: no table sampled" ||
    fail "$q: missing resume: tables were sampled first"
done
echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
