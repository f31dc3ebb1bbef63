#!/usr/bin/env bash
# `make test-slurm`: the quick study through a throw-away single-node SLURM cluster on this machine
# (tests/slurm/local_slurm.sh, no job accounting) with the shipped profile workflow/profiles/slurm,
# unedited, and alongside it the same study locally. Every output file except the per-rule logs must be
# byte-identical (cmp): tables (CSV, parquet, JSON), summary.md and the figures (PNG, PDF).
# The cluster is stopped on exit, also after a failure. Needs root or sudo, and .venv with the
# executor plugin (`make cluster-venv`, which `make test-slurm` runs first).
set -euo pipefail
cd "$(dirname "$0")/../.."

STUDY=config/studies/quick.yaml
OUT=results/test_slurm
# The quick study makes 5 SLURM jobs (2 + 3 group jobs of the two solver groups, every other rule local);
# more means the profile's groups or the localrules were lost (82 jobs without them).
MAX_JOBS=6
SUDO=
[ "$(id -u)" = 0 ] || SUDO=sudo

fail() { echo "test-slurm: FAILED: $*" >&2; exit 1; }
slurm_pid=
cleanup() {
  # a SLURM run still going (the local run failed, or Ctrl-C): cancel its jobs, so that
  # Snakemake sees them end and exits, then stop the cluster
  if [ -n "$slurm_pid" ] && kill -0 "$slurm_pid" 2>/dev/null; then
    squeue -h -o %i 2>/dev/null | xargs -r scancel 2>/dev/null || true
    kill -TERM "$slurm_pid" 2>/dev/null || true
    for _ in $(seq 120); do kill -0 "$slurm_pid" 2>/dev/null || break; sleep 1; done
    kill -KILL "$slurm_pid" 2>/dev/null || true
  fi
  $SUDO tests/slurm/local_slurm.sh stop || true
}
trap cleanup EXIT

t0=$(date +%s)
$SUDO tests/slurm/local_slurm.sh start
t1=$(date +%s)

rm -rf "$OUT"
mkdir -p "$OUT"
# The local run goes alongside the SLURM run, whose jobs leave the CPUs idle while they queue
# and between status queries (disjoint outputs, so the two Snakemake runs do not lock each other).
echo "test-slurm: $STUDY through SLURM (log: $OUT/slurm.log) and locally (log: $OUT/local.log)"
.venv/bin/snakemake --profile workflow/profiles/slurm reproduce_paper \
  --config study="$STUDY" results="$OUT/slurm" > "$OUT/slurm.log" 2>&1 &
slurm_pid=$!
.venv/bin/snakemake --cores all reproduce_paper \
  --config study="$STUDY" results="$OUT/local" > "$OUT/local.log" 2>&1 ||
  { tail -40 "$OUT/local.log"; fail "the local run failed"; }
t2=$(date +%s)
wait "$slurm_pid" || { tail -40 "$OUT/slurm.log"; fail "the SLURM run failed"; }
slurm_pid=
t3=$(date +%s)
jobs=$(grep -c "has been submitted with SLURM jobid" "$OUT/slurm.log" || true)

list() { (cd "$1" && find . -type f ! -path './logs/*' | sort); }
list "$OUT/local" > "$OUT/local.files"
list "$OUT/slurm" > "$OUT/slurm.files"
diff "$OUT/local.files" "$OUT/slurm.files" || fail "the two runs wrote different files (< local, > SLURM)"
differ=0
while read -r f; do
  cmp "$OUT/local/$f" "$OUT/slurm/$f" || differ=$((differ + 1))
done < "$OUT/local.files"
[ "$differ" = 0 ] || fail "$differ files differ between the SLURM and the local run"
[ "$jobs" -ge 1 ] && [ "$jobs" -le "$MAX_JOBS" ] || fail "$jobs SLURM jobs submitted, expected 1..$MAX_JOBS"

kinds=$(sed 's/.*\.//' "$OUT/local.files" | sort | uniq -c | awk '{printf "%s%s %s", sep, $1, $2; sep=", "}')
echo "test-slurm: OK: $(wc -l < "$OUT/local.files") files byte-identical ($kinds); $jobs SLURM jobs"
echo "test-slurm: seconds: cluster start $((t1 - t0)), local run $((t2 - t1)) and SLURM run $((t3 - t1)) side by side, total $((t3 - t0)) (+ stop)"
