#!/usr/bin/env bash
# `make test-slurm`: the quick study and the quick spatial study (CoGiRo), one after the other,
# through a throw-away single-node SLURM cluster on this machine (tests/slurm/local_slurm.sh, no job
# accounting) with the shipped profile workflow/profiles/slurm, unedited, and alongside each the
# same study locally. Every output file except the per-rule logs must be
# byte-identical (cmp): tables (CSV, parquet, JSON), summary.md and the figures (PNG, PDF).
# The cluster is stopped on exit, also after a failure. Needs root or sudo, and .venv with the
# executor plugin (`make cluster-venv`, which `make test-slurm` runs first).
set -euo pipefail
cd "$(dirname "$0")/../.."

OUT=results/test_slurm
# The studies, each with the most SLURM jobs it may submit: the quick study makes 3 (2 + 1 group jobs
# of the two solver groups, every other rule local; 82 jobs without them and before the DOE and E
# sweep indices became one job per shard of tests / moduli), the quick spatial study 3
# (tests/test_cluster_profile.py counts them in a dry run). More means the profile's groups or the
# localrules were lost. `TEST_SLURM_STUDIES="quick"` runs only the first.
STUDIES=${TEST_SLURM_STUDIES:-"quick quick_spatial"}
declare -A MAX_JOBS=([quick]=4 [quick_spatial]=4)
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

# One study through SLURM and, alongside, locally; every output but the logs compared with cmp.
run_study() {
  local name=$1 study=config/studies/$1.yaml out=$OUT/$1 ta tb tc jobs differ f kinds
  mkdir -p "$out"
  ta=$(date +%s)
  # The local run goes alongside the SLURM run, whose jobs leave the CPUs idle while they queue
  # and between status queries (disjoint outputs, so the two Snakemake runs do not lock each other).
  echo "test-slurm: $study through SLURM (log: $out/slurm.log) and locally (log: $out/local.log)"
  .venv/bin/snakemake --profile workflow/profiles/slurm reproduce_paper \
    --config study="$study" results="$out/slurm" > "$out/slurm.log" 2>&1 &
  slurm_pid=$!
  .venv/bin/snakemake --cores all reproduce_paper \
    --config study="$study" results="$out/local" > "$out/local.log" 2>&1 ||
    { tail -40 "$out/local.log"; fail "$name: the local run failed"; }
  tb=$(date +%s)
  wait "$slurm_pid" || { tail -40 "$out/slurm.log"; fail "$name: the SLURM run failed"; }
  slurm_pid=
  tc=$(date +%s)
  jobs=$(grep -c "has been submitted with SLURM jobid" "$out/slurm.log" || true)

  list() { (cd "$1" && find . -type f ! -path './logs/*' | sort); }
  list "$out/local" > "$out/local.files"
  list "$out/slurm" > "$out/slurm.files"
  diff "$out/local.files" "$out/slurm.files" || fail "$name: the two runs wrote different files (< local, > SLURM)"
  differ=0
  while read -r f; do
    cmp "$out/local/$f" "$out/slurm/$f" || differ=$((differ + 1))
  done < "$out/local.files"
  [ "$differ" = 0 ] || fail "$name: $differ files differ between the SLURM and the local run"
  [ "$jobs" -ge 1 ] && [ "$jobs" -le "${MAX_JOBS[$name]}" ] ||
    fail "$name: $jobs SLURM jobs submitted, expected 1..${MAX_JOBS[$name]}"

  kinds=$(sed 's/.*\.//' "$out/local.files" | sort | uniq -c | awk '{printf "%s%s %s", sep, $1, $2; sep=", "}')
  echo "test-slurm: $name OK: $(wc -l < "$out/local.files") files byte-identical ($kinds); $jobs SLURM jobs"
  echo "test-slurm: $name seconds: local run $((tb - ta)) and SLURM run $((tc - ta)) side by side"
}

for name in $STUDIES; do
  [ -f "config/studies/$name.yaml" ] && [ -n "${MAX_JOBS[$name]:-}" ] || fail "unknown study $name (TEST_SLURM_STUDIES)"
  run_study "$name"
done
echo "test-slurm: seconds: cluster start $((t1 - t0)), total $(($(date +%s) - t0)) (+ stop)"
