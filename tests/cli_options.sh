#!/bin/bash
# An option without its value, on every command (cli/option_value.h): exit
# 2, "<option> needs a value", nothing written, whether the option is last
# or followed by another option. The next option had been taken as the
# value: `sample --out --quiet` sampled 32 MB of tables into a folder named
# "--quiet", `fit sigmoid --out --quiet` wrote a weights file so named, and
# `build --out --quiet` ran the whole build, each with exit 0. A value may
# still begin with one dash (a negative number) or be a file named
# "./--name".
set -u
bin=${SKYFIT_BIN:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0
cases=(
  "sample|--out --resolution --atmosphere --scene --orders --threads --parameterization --stop-fraction"
  "build|--out --header-c --header-glsl --prefix --resolution --views --samples --timing-points --repetitions --seed --mlp-epochs --mlp-samples --mlp-restarts --mlp-normalise --mlp-normalise-cap --mlp-loss-floor --cache-limit --threads"
  "report|--out --resolution --views --samples --seed --cache-limit --threads"
  "eval transmittance|--atmosphere --model --to --to-distance"
  "eval sky_radiance|--tables --resolution"
  "fit sigmoid|--out --scene --atmosphere --check --grid"
  "fit spectral4|--out --scene --atmosphere --cache --cache-limit --resolution --orders --threads"
  "fit hosek|--out --scene --tables --samples --check --scale --elevations --grid --resolution"
  "fit preetham|--out --check --scale"
  "fit mlp-transmittance|--out --layers --epochs --tables --dump-dataset --seed --input-map --target-root --resolution"
  "fit mlp-scattering|--out --loss --batch --target --split --normalise --normalise-cap --atmosphere"
  "fit mlp|--data --inputs --layers --out --epochs --init-weights"
  "codegen|--weights --lang --out --name --prefix --baselines --naive-steps --atmosphere --scene"
)
for c in "${cases[@]}"; do
  read -r -a words <<<"${c%%|*}"
  for opt in ${c#*|}; do
    for after in "" "--quiet"; do
      mkdir "$tmp/run"
      rc=0
      (cd "$tmp/run" && "$bin" "${words[@]}" "$opt" $after </dev/null >"$tmp/out" 2>"$tmp/err") || rc=$?
      left=$(ls -A "$tmp/run")
      if [ $rc -eq 2 ] && grep -q -- "$opt needs a value" "$tmp/err" && [ -z "$left" ]; then
        passed=$((passed + 1))
      else
        echo "FAIL ${words[*]} $opt $after: exit $rc, wrote '$left': $(head -c 300 "$tmp/err")"
        failed=$((failed + 1))
      fi
      rm -rf "$tmp/run"
    done
  done
done
echo "ok   $passed option-without-value cases: exit 2, named, nothing written"
# One dash is a value: the distance's own check answers, not "needs a value".
rc=0
printf 'h_km,mu\n0,1\n' | "$bin" eval transmittance --to-distance -3 >/dev/null 2>"$tmp/err" || rc=$?
if [ $rc -eq 2 ] && grep -q -- "--to-distance: expected a distance >= 0 in km, got '-3'" "$tmp/err"; then
  echo "ok   --to-distance -3 is read as a value: $(cat "$tmp/err")"; passed=$((passed + 1))
else echo "FAIL --to-distance -3: exit $rc, $(cat "$tmp/err")"; failed=$((failed + 1)); fi
# A file named "--w.json" is given as ./--w.json.
mkdir "$tmp/dash"
rc=0
(cd "$tmp/dash" && "$bin" fit sigmoid --grid 8x8 --out ./--w.json --quiet >/dev/null 2>"$tmp/err") || rc=$?
if [ $rc -eq 0 ] && [ -s "$tmp/dash/--w.json" ]; then
  echo "ok   --out ./--w.json writes --w.json"; passed=$((passed + 1))
else echo "FAIL --out ./--w.json: exit $rc, $(cat "$tmp/err")"; failed=$((failed + 1)); fi
# A help text that cannot be written (a full disk) exits 1, naming stdout
# (it had exited 0).
if [ -w /dev/full ]; then
  for cmd in "" build "fit sigmoid" eval; do
    rc=0
    "$bin" $cmd --help >/dev/full 2>"$tmp/err" || rc=$?
    if [ $rc -eq 1 ] && grep -q "writing to stdout failed" "$tmp/err"; then
      echo "ok   skyfit $cmd --help to a full disk: exit 1"; passed=$((passed + 1))
    else echo "FAIL skyfit $cmd --help to a full disk: exit $rc, $(cat "$tmp/err")"; failed=$((failed + 1)); fi
  done
fi
echo "$passed passed, $failed failed"
[ $failed -eq 0 ]
