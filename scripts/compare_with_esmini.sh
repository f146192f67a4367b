#!/usr/bin/env bash
# Plays OpenSCENARIO files in esmini and in emrm and prints, per entity, the largest position and
# speed difference over the first 10 s (docs/import.md, "Comparing with esmini's recording").
#   scripts/compare_with_esmini.sh ESMINI_BUILD EMRM [--disable-controllers] FILE.xosc...
# ESMINI_BUILD is esmini's build folder holding EnvironmentSimulator/Applications/{esmini,replayer};
# EMRM the emrm binary. --disable-controllers runs esmini with --disable_controllers (every entity on
# its default controller, as emrm plays the storyboard before the threat onset). Not a test: no
# test runs esmini (tests/unit/openscenario/esmini holds recordings made with it).
set -uo pipefail

if (($# < 3)); then
  sed -n '2,8p' "$0" >&2
  exit 2
fi
readonly apps=$1/EnvironmentSimulator/Applications emrm=$(realpath "$2")
shift 2
extra=()
if [[ $1 == --disable-controllers ]]; then
  extra=(--disable_controllers)
  shift
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for file in "$@"; do
  name=$(basename "$file" .xosc)
  dir=$work/$name
  mkdir -p "$dir"
  scenario=$(realpath "$file")
  (cd "$dir" && timeout 120 "$apps/esmini/esmini" --headless --osc "$scenario" "${extra[@]}" --fixed_timestep 0.01 \
    --record sim.dat >/dev/null 2>&1 && "$apps/replayer/dat2csv" sim.dat --precision 6 >/dev/null 2>&1)
  err=$(timeout 300 "$emrm" import "$scenario" --trace "$dir/emrm.csv" --trace-s 10 2>&1 >/dev/null | head -1)
  # More than five declared numeric parameters: the first one as the scene's factor (the trace
  # does not depend on the factors).
  if [[ ! -f $dir/emrm.csv ]] && grep -q -- "--factors A,B" <<<"$err"; then
    first=$(sed 's/.*numeric parameters (\([^,)]*\).*/\1/' <<<"$err")
    err=$(timeout 300 "$emrm" import "$scenario" --factors "$first" --trace "$dir/emrm.csv" --trace-s 10 2>&1 >/dev/null |
      head -1)
  fi
  if [[ ! -f $dir/emrm.csv ]]; then
    echo "$name: IMPORT FAILED: $err"
    continue
  fi
  python3 - "$name" "$dir/sim.csv" "$dir/emrm.csv" <<'EOF'
import csv, math, sys
name, esmini_csv, emrm_csv = sys.argv[1:4]
recorded = {}
for r in csv.reader(open(esmini_csv)):
    if r[0].startswith('time'):
        continue
    recorded.setdefault(r[2].strip(), {})[round(float(r[0]), 3)] = (float(r[3]), float(r[4]), float(r[9]))
played = {}
for r in csv.DictReader(open(emrm_csv)):
    played.setdefault(r['actor'], {})[round(float(r['t']), 3)] = (float(r['x']), float(r['y']), float(r['speed']))
print(name + ':')
for actor in sorted(played):
    worst_p, worst_v, n = (0.0, None), (0.0, None), 0
    for t, (x, y, v) in played[actor].items():
        if t > 10.0001 or t not in recorded.get(actor, {}):
            continue
        ex, ey, ev = recorded[actor][t]
        n += 1
        d = math.hypot(x - ex, y - ey)
        if d > worst_p[0]:
            worst_p = (d, t)
        if abs(abs(v) - abs(ev)) > worst_v[0]:
            worst_v = (abs(abs(v) - abs(ev)), t)
    ok = worst_p[0] <= 0.05 and worst_v[0] <= 0.05 and n > 0
    print('   %s %s pos %.4f@%s v %.4f@%s n=%d' % ('OK ' if ok else 'BAD', actor, worst_p[0], worst_p[1], worst_v[0],
                                                  worst_v[1], n))
EOF
done
