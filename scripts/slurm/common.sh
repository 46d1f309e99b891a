# Shared by scripts/slurm/submit and scripts/slurm/resubmit (sourced, not run).

die() {
  echo "$(basename "$0"): error: $*" >&2
  exit 2
}

# The first field of `sbatch --parsable` ("123" or "123;cluster").
job_id() { echo "${1%%;*}"; }

# --cpus-per-task / -c among the sbatch options given, or 1.
cpus_per_task() {
  local cpus=1
  while [ $# -gt 0 ]; do
    case "$1" in
      --cpus-per-task=*) cpus="${1#*=}" ;;
      --cpus-per-task | -c) shift; cpus="${1:-1}" ;;
      -c*) cpus="${1#-c}" ;;
    esac
    shift
  done
  echo "$cpus"
}

# A task asking for more CPUs than any node has would pend for ever: refuse it here.
check_cpus_fit() {
  local cpus max
  cpus="$(cpus_per_task "$@")"
  [[ "$cpus" =~ ^[0-9]+$ ]] || die "--cpus-per-task '$cpus' is not a number"
  if ! max="$(sinfo -h -N -o '%c' 2>/dev/null | tr -d '+' | sort -n | tail -n 1)" || [ -z "$max" ]; then
    echo "$(basename "$0"): warning: sinfo gave no node sizes; --cpus-per-task=$cpus not checked" >&2
    return 0
  fi
  [ "$cpus" -le "$max" ] || die "--cpus-per-task=$cpus but the largest node has $max CPUs (sinfo): the tasks would pend for ever"
}

# --merge-time=T / --merge-mem=M (submit, resubmit): the merge job's --time / --mem.
is_merge_option() { case "$1" in --merge-time=* | --merge-mem=*) return 0 ;; esac; return 1; }
merge_option() {
  case "$1" in
    --merge-time=*) echo "--time=${1#--merge-time=}" ;;
    --merge-mem=*) echo "--mem=${1#--merge-mem=}" ;;
  esac
}

# Job ids of this sweep (from OUT/jobs, KEY=array or merge) that SLURM still lists as pending or
# running.
busy_jobs() {
  local ours queued
  ours="$(sed -n "s/.* $1=\([0-9]*\).*/\1/p" "$OUT/jobs" 2>/dev/null | sort -u)"
  queued="$(squeue --me -h -o '%F %T' 2>/dev/null | awk '{print $1}' | sort -u)" || die "squeue failed"
  comm -12 <(echo "$ours") <(echo "$queued") | tr '\n' ' ' | sed 's/ *$//'
}

# Submits merge.sbatch to run after every task of array job $1 has ended, whatever its state
# (afterany: a cancelled or failed task must not leave the merge waiting for ever; no $1: at once).
# merge itself refuses an incomplete set, so a merge after a failed task fails and names the
# shards to rerun.
submit_merge() {
  local after=() out
  if [ -n "${1:-}" ]; then after=(--dependency="afterany:$1" --kill-on-invalid-dep=yes); fi
  out="$(sbatch --parsable --chdir="$WORKDIR" "${after[@]+"${after[@]}"}" \
           --output="$OUT/logs/merge_%j.log" --export="ALL,AL_SWEEP_JOB=$OUT/sweep.job" \
           "${MERGE_OPTIONS[@]+"${MERGE_OPTIONS[@]}"}" "$SLURM_SCRIPTS/merge.sbatch")" || die "sbatch of the merge job failed"
  job_id "$out"
}
