#!/usr/bin/env bash
# Wall time of the paper study from a warm .venv: every job re-run into a scratch results folder.
#   bash benchmarks/time_reproduce.sh            # paper resolution
#   STUDY=config/studies/quick.yaml bash benchmarks/time_reproduce.sh
#   ALL=1 bash benchmarks/time_reproduce.sh      # what `make reproduce` runs: the paper study, the same
#                                                # study in physical mode, then their comparison and
#                                                # the error budget (each step timed, and the total)
# BIN=/path/to/venv/bin uses another environment's snakemake (no `make venv`).
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-.venv/bin}
if [ "$BIN" = .venv/bin ]; then make venv >/dev/null; fi
EXTRA=${EXTRA:-}
STUDY=${STUDY:-config/studies/paper.yaml}
OUT=${OUT:-results/bench}
rm -rf "$OUT"
mkdir -p "$(dirname "$OUT")"
echo "CPU: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
if [ "${ALL:-0}" = 1 ]; then
  mkdir -p "$OUT"
  CMP="$OUT/comparison.yaml"
  "$BIN/python" - "$OUT" "$CMP" <<'PY'
import sys, yaml
out, path = sys.argv[1], sys.argv[2]
c = yaml.safe_load(open("config/comparisons/paper_vs_physical.yaml"))
c["paper"]["results"], c["physical"]["results"] = f"{out}/paper", f"{out}/physical"
c["page"], c["folder"] = f"{out}/comparison.md", f"{out}/comparison"
yaml.safe_dump(c, open(path, "w"))
PY
  total=0
  step() {  # name, then the snakemake arguments
    local name=$1; shift
    local s=$(date +%s.%N)
    /usr/bin/time -v "$BIN/snakemake" "$@" --cores all 2> "$OUT/$name.time.log" >/dev/null || { tail -30 "$OUT/$name.time.log"; exit 1; }
    local dt=$(echo "$(date +%s.%N) - $s" | bc)
    total=$(echo "$total + $dt" | bc)
    echo "$name: wall $dt s; jobs run: $(grep -c "Finished job" "$OUT/$name.time.log" || true); $(grep -E "Maximum resident set size" "$OUT/$name.time.log" | sed 's/^\s*//')"
  }
  step paper reproduce_paper --forceall --config study=config/studies/paper.yaml results="$OUT/paper" comparison="$CMP"
  step physical reproduce_paper --forceall --config study=config/studies/physical.yaml results="$OUT/physical" comparison="$CMP"
  step comparison reproduce_comparison --forcerun budget_design budget comparison --config results="$OUT/paper" comparison="$CMP"
  echo "make reproduce equivalent: total wall $total s"
  exit 0
fi
start=$(date +%s.%N)
/usr/bin/time -v "$BIN/snakemake" reproduce_paper --cores all --forceall $EXTRA --config study="$STUDY" results="$OUT" 2> "$OUT.time.log" || { tail -30 "$OUT.time.log"; exit 1; }
end=$(date +%s.%N)
jobs=$(ls "$OUT"/logs | wc -l)
echo "study $STUDY: wall $(echo "$end - $start" | bc) s; jobs run: $(grep -c "Finished job" "$OUT.time.log" || true) (solver jobs with logs: $jobs)"
grep -E "Maximum resident set size" "$OUT.time.log" | sed 's/^\s*/snakemake process /'
