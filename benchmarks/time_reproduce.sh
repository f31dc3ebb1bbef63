#!/usr/bin/env bash
# Wall time of the paper study from a warm .venv: every job re-run into a scratch results folder.
#   bash benchmarks/time_reproduce.sh            # paper resolution
#   STUDY=config/studies/quick.yaml bash benchmarks/time_reproduce.sh
set -euo pipefail
cd "$(dirname "$0")/.."
make venv >/dev/null
EXTRA=${EXTRA:-}
STUDY=${STUDY:-config/studies/paper.yaml}
OUT=${OUT:-results/bench}
rm -rf "$OUT"
mkdir -p "$(dirname "$OUT")"
start=$(date +%s.%N)
/usr/bin/time -v .venv/bin/snakemake reproduce_paper --cores all --forceall $EXTRA --config study="$STUDY" results="$OUT" 2> "$OUT.time.log" || { tail -30 "$OUT.time.log"; exit 1; }
end=$(date +%s.%N)
jobs=$(ls "$OUT"/logs | wc -l)
echo "study $STUDY: wall $(echo "$end - $start" | bc) s; jobs run: $(grep -c "Finished job" "$OUT.time.log" || true) (solver jobs with logs: $jobs)"
grep -E "Maximum resident set size" "$OUT.time.log" | sed 's/^\s*/snakemake process /'
