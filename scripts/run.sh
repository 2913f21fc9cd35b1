#!/usr/bin/env bash
# Set-up, Release build of the hyfal binary if needed, then `hyfal ARGS`. With no ARGS: the main
# job, which shows what hyfal is for in a few minutes: seed 002's Table 2 (HyDICE against RRT and
# RRT[D*] on aircraft conflict resolution) reproduced beside the paper's numbers, its figure, a
# picture of one collision HyDICE found, and where the files are.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" hyfal  # only the binary: scripts/test.sh builds the tests and benchmarks
hyfal="${BUILD_DIR:-$root/build}/app/hyfal"
if [ $# -gt 0 ]; then
  exec "$hyfal" "$@"
fi

cd "$root"
db=results/hyfal.sqlite
out=results/main-job  # not results/tables, which holds the committed tables
witnesses=results/witnesses
table=plaku-table2
profile=quick
status=0
"$hyfal" reproduce "$table" --profile "$profile" --db "$db" --witness-dir "$witnesses" --out-dir "$out" || status=$?

# One collision HyDICE found on a random instance (the largest N), drawn over the aircraft's paths.
witness=$(sqlite3 -readonly "$db" "SELECT witness FROM trials WHERE experiment = '$table/$profile' AND method = 'hydice'
  AND status = 'falsified' AND json_extract(instance, '$.example') = 'random'
  ORDER BY json_extract(instance, '$.N') DESC, trial_index LIMIT 1" 2>/dev/null || true)
picture=""
if [ -n "$witness" ] && "$hyfal" plot --witness "$witness" --out "$out/$table-witness.png" >/dev/null; then
  picture="$out/$table-witness.png"
fi

echo
echo "Files of this main job (rerunning scripts/run.sh resumes: stored trials are not run again):"
echo "  table, beside the paper's numbers:  $out/$table.md (and .csv)"
for figure in "$out/$table.png" "$picture"; do
  [ -n "$figure" ] && [ -f "$figure" ] && echo "  figure:                             $figure (and .svg)"
done
echo "  results database (every trial):     $db    (hyfal table --db $db)"
echo "  witnesses (one per falsified trial): $witnesses/$table/$profile/    (hyfal validate FILE, hyfal plot --witness FILE)"
echo "  other paper tables:                 hyfal list; hyfal reproduce ID --profile smoke|quick|paper --plan"
exit "$status"
