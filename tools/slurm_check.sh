#!/usr/bin/env bash
# Checks the cluster profile (profiles/slurm/) on a real Slurm scheduler: the regime-map stage
# of the CI config run through Slurm gives byte-identical outputs to a local run.
#
#   bash tools/slurm_check.sh [--record FILE]
#
#  1. starts a single-node Slurm on this machine (tools/slurm.sh start; installs slurm-wlm and
#     munge from apt if missing);
#  2. copies the working tree (git ls-files -co --exclude-standard, not .venv/) into two
#     scratch copies under $SLURM_CHECK_DIR (default /tmp/impactdamper-slurm-check), with fixed
#     mtimes so that Snakemake reruns nothing upstream of the maps, and without the map outputs
#     (the committed figures/map_* of the full config), so that every target is made anew;
#     a dry run checks that only compiled_warm_up, map_chunk, map_gather, map_curves and fig_regime_map would run
#     (the runs allow only these rules: the warm-up a copy needs would otherwise rerun every job
#     that waits for it, the gap scan behind the maps' located-case marker among them);
#  3. runs the map stage with --configfile config/ci.yaml: through Slurm in copy `slurm`
#     (--profile profiles/slurm) and locally (--cores 2) in copy `local`, one after the other,
#     both with this repository's .venv/bin/snakemake and PYTHONPATH=<copy>/src (the venv's
#     editable install would otherwise import /work/main/src);
#  4. compares every output with cmp, one line per file and "N identical, M differ";
#     the timing JSON files (results/maps/<map>/chunk_<n>.json and
#     results/benchmarks/map_<map>_timing.json: wall and processor times, load, start and end
#     times) are produced but not compared: they differ from run to run by design;
#  5. prints the Slurm job ids Snakemake submitted and their states in squeue, and stops the
#     cluster (tools/slurm.sh stop), also on failure.
# Exit status: 0 only when both runs succeed and every compared file is identical.
# With --record FILE, the whole output is also saved to FILE under a first line with the
# date, the command and the wall time.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
RECORD=""
if [ "${1:-}" = "--record" ]; then RECORD=$(realpath -m "${2:?--record needs a file}"); shift 2; fi
[ $# = 0 ] || { echo "usage: $0 [--record FILE]" >&2; exit 2; }

WORK="${SLURM_CHECK_DIR:-/tmp/impactdamper-slurm-check}"
SNAKEMAKE="$ROOT/.venv/bin/snakemake"
PYTHON="$ROOT/.venv/bin/python"
CONFIG=config/ci.yaml
# The CI config's coarse grids, written in place in the scratch copies (its output_root keeps a
# coarse run out of a clone's record; here the copies' committed outputs are the map stage's
# upstream inputs, and the copies are thrown away).
CONFIG_ARGS=(--configfile "$CONFIG" --config output_root=.)
[ -x "$SNAKEMAKE" ] || { echo "slurm_check: $SNAKEMAKE missing: run tools/setup.sh" >&2; exit 1; }

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.1f", b - a}'; }
T0=$(now)
START_DATE=$(date -u '+%Y-%m-%d %H:%M:%S UTC')

OUT=$(mktemp)
exec 3>&1 4>&2
exec > >(tee "$OUT") 2>&1
TEE_PID=$!

cluster_started=0
finish() {
  local rc=$?
  if [ "$cluster_started" = 1 ]; then
    echo "== stop the cluster"
    bash "$ROOT/tools/slurm.sh" stop || true
  fi
  local wall; wall=$(secs "$T0" "$(now)")
  echo "time: whole check ${wall} s (exit $rc)"
  exec 1>&3 2>&4
  wait "$TEE_PID" 2>/dev/null || true
  if [ -n "$RECORD" ]; then
    { echo "# ${START_DATE}: bash tools/slurm_check.sh --record ${RECORD#"$ROOT"/} -- wall time ${wall} s, exit ${rc}, on $(hostname -s) ($(nproc) CPUs)"
      cat "$OUT"; } >"$RECORD"
  fi
  rm -f "$OUT"
  exit "$rc"
}
trap finish EXIT

# Targets: the regime-map outputs of workflow/rules/sweeps.smk (rules compiled_warm_up, map_chunk, map_gather,
# map_curves, fig_regime_map) for the CI config's maps and chunk count.
read -r -a MAPS <<<"$(grep -o '^SWEEP_MAPS = \[.*\]' "$ROOT/workflow/rules/sweeps.smk" | tr -d '[]",' | cut -d= -f2)"
CHUNKS=$("$PYTHON" -c 'import sys, yaml; print(yaml.safe_load(open(sys.argv[1]))["maps"]["chunks"])' "$ROOT/$CONFIG")
COMPARED=()   # outputs compared byte for byte
TIMING=()     # outputs produced, not compared (timings)
for m in "${MAPS[@]}"; do
  for ((c = 0; c < CHUNKS; c++)); do
    COMPARED+=("results/maps/$m/chunk_$c.csv")
    TIMING+=("results/maps/$m/chunk_$c.json")
  done
  COMPARED+=("figures/map_$m.csv" "figures/map_${m}_settings.json" "figures/map_${m}_curves.csv"
             "figures/map_$m.pdf" "figures/map_$m.png")
  TIMING+=("results/benchmarks/map_${m}_timing.json")
done
TARGETS=("${COMPARED[@]}" "${TIMING[@]}")
echo "== slurm_check: maps ${MAPS[*]}, ${CHUNKS} chunks each ($CONFIG): ${#COMPARED[@]} files compared, ${#TIMING[@]} timing files not compared"

echo "== start the cluster (tools/slurm.sh start)"
t=$(now)
cluster_started=1
bash "$ROOT/tools/slurm.sh" start
export SLURM_CONF="${SLURM_STATE:-/tmp/impactdamper-slurm}/slurm.conf"
echo "time: cluster start $(secs "$t" "$(now)") s"
sinfo
echo "versions: $(sinfo -V), snakemake $("$SNAKEMAKE" --version), snakemake-executor-plugin-slurm $("$PYTHON" -c \
  'from importlib.metadata import version; print(version("snakemake-executor-plugin-slurm"))'); load average $(cut -d' ' -f1-3 /proc/loadavg)"

echo "== scratch copies of the working tree in $WORK"
t=$(now)
rm -rf "$WORK"
mkdir -p "$WORK/slurm"
(cd "$ROOT" && git ls-files -co --exclude-standard -z) \
  | (cd "$ROOT" && while IFS= read -r -d '' f; do
       case "$f" in .venv/*) continue ;; esac
       if [ -e "$f" ] || [ -L "$f" ]; then printf '%s\0' "$f"; fi
     done) \
  | tar -C "$ROOT" --null -T - -cf - | tar -C "$WORK/slurm" -xf -
# Tracked files deleted in the working tree (say, an output being regenerated) come from HEAD.
while IFS= read -r -d '' f; do
  case "$f" in .venv/*) continue ;; esac
  mkdir -p "$WORK/slurm/$(dirname "$f")"
  git -C "$ROOT" show "HEAD:$f" >"$WORK/slurm/$f" && echo "deleted in the working tree, taken from HEAD: $f"
done < <(git -C "$ROOT" ls-files -d -z)
# Fixed mtimes, so that nothing upstream of the maps looks outdated (the copy's own mtimes are
# those of the checkout): sources a day older than the committed outputs (figures/,
# paper/generated/), which must be strictly newer than their rules' scripts.
find "$WORK/slurm" -exec touch -h -d '2020-01-01 00:00:00' {} +
find "$WORK/slurm/figures" "$WORK/slurm/paper/generated" -exec touch -h -d '2020-01-02 00:00:00' {} +
# The committed figures of the full config are not kept: every target is made anew.
(cd "$WORK/slurm" && rm -f "${TARGETS[@]}")
cp -a "$WORK/slurm" "$WORK/local"
echo "$(find "$WORK/slurm" -type f | wc -l) files in each copy ($(secs "$t" "$(now)") s)"

# The map stage's rules: the only ones the runs may use (other rules' outputs are taken as they are).
MAP_RULES=(compiled_warm_up map_chunk map_gather map_curves fig_regime_map)

# jobstats LOG: the first "Job stats" table of a Snakemake log
jobstats() { awk '/^Job stats:/ {n++} n == 1 && /^$/ {exit} n == 1' "$1"; }

# run NAME ARGS...: the map stage in copy NAME; log in $WORK/NAME.log
run() {
  local name=$1; shift
  local t rc=0
  t=$(now)
  (cd "$WORK/$name" && PYTHONPATH="$WORK/$name/src" "$SNAKEMAKE" "${TARGETS[@]}" "$@" "${CONFIG_ARGS[@]}" \
    --allowed-rules "${MAP_RULES[@]}") \
    >"$WORK/$name.log" 2>&1 || rc=$?
  echo "time: $name run $(secs "$t" "$(now)") s (exit $rc; log $WORK/$name.log)"
  if [ "$rc" != 0 ]; then tail -n 40 "$WORK/$name.log"; fi
  return "$rc"
}

# The jobs to run: only the map rules (anything else means the copy's mtimes made Snakemake
# rerun an upstream stage, which this check does not want).
(cd "$WORK/slurm" && "$SNAKEMAKE" "${TARGETS[@]}" -n --quiet rules "${CONFIG_ARGS[@]}" \
  --allowed-rules "${MAP_RULES[@]}") >"$WORK/dryrun.log" 2>&1 \
  || { cat "$WORK/dryrun.log"; exit 1; }
jobstats "$WORK/dryrun.log"
other=$(jobstats "$WORK/dryrun.log" | awk 'NF == 2 && $2 ~ /^[0-9]+$/ && $1 != "total" {print $1}' \
  | grep -vxE 'compiled_warm_up|map_chunk|map_gather|map_curves|fig_regime_map' || true)
[ -z "$other" ] || { echo "slurm_check: rules other than the map stage would run: $other" >&2; exit 1; }

echo "== Slurm run: snakemake --profile profiles/slurm --configfile $CONFIG <map targets>"
(cd "$WORK/slurm" && PYTHONPATH="$WORK/slurm/src" "$PYTHON" -c \
  'import impactdamper, sys; print("impactdamper from", impactdamper.__file__)')
# Local-cluster overrides only: status queries sooner (the site default is 20 s), and no
# retry that could hide a failure.
slurm_rc=0
run slurm --profile profiles/slurm --slurm-init-seconds-before-status-checks 2 --retries 0 \
  --slurm-keep-successful-logs || slurm_rc=$?
echo "-- jobs (Snakemake's job stats):"
jobstats "$WORK/slurm.log"
echo "-- Slurm submissions (snakemake's slurm executor):"
grep -E "submitted with SLURM jobid" "$WORK/slurm.log" | sed 's/^/   /' || true
mapfile -t JOBIDS < <(grep -oE "SLURM jobid [0-9]+" "$WORK/slurm.log" | awk '{print $3}')
echo "-- squeue --states=all for those ${#JOBIDS[@]} jobs:"
if [ "${#JOBIDS[@]}" -gt 0 ]; then
  squeue --states=all -j "$(IFS=,; echo "${JOBIDS[*]}")" -o '%.6i %.9P %.36k %.10T %.8M %.4C %.7m %N'
fi
if grep -q "Falling back to 'sacct'" "$WORK/slurm.log"; then status_cmd=sacct; else status_cmd=squeue; fi
echo "-- job status read with: $status_cmd (slurm-status-command in profiles/slurm/config.yaml); sacct here: $(sacct 2>&1 | head -n1)"

echo "== local run: snakemake --cores 2 --configfile $CONFIG <map targets>"
local_rc=0
run local --cores 2 || local_rc=$?

echo "== compare (cmp) slurm/ against local/"
same=0; differ=0
for f in "${COMPARED[@]}"; do
  a="$WORK/slurm/$f"; b="$WORK/local/$f"
  if [ ! -f "$a" ] || [ ! -f "$b" ]; then
    echo "MISSING   $f"; differ=$((differ + 1))
  elif cmp -s "$a" "$b"; then
    echo "identical $f ($(stat -c %s "$a") bytes)"; same=$((same + 1))
  else
    echo "DIFFER    $f: $(cmp "$a" "$b" 2>&1 | head -n1)"; differ=$((differ + 1))
  fi
done
echo "not compared (timings, differ by design): ${TIMING[*]}"
echo "$same identical, $differ differ"

[ "$slurm_rc" = 0 ] && [ "$local_rc" = 0 ] && [ "$differ" = 0 ]
