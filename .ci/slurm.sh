#!/usr/bin/env bash
# The Slurm recipes of docs/distributed.md on a real single-node Slurm
# cluster started here: munged, slurmctld and slurmd from Debian's packages,
# with their key, socket, configuration, state, spool and logs in a scratch
# directory that is removed (daemons stopped) on exit.
#
# It submits the batch scripts the doc shows, docs/farm/render.sbatch and
# docs/farm/frames.sbatch, as they are; only the sizes (array range, CPUs,
# memory, time) are given on the sbatch command line and the paths and
# sample counts in the environment. Then:
#   1. 4 tiles × 2 passes and a dependent merge job: pass 0's tiles merge
#      byte-identical to a single-process render, the two passes averaged to
#      the average of two single-process pass renders;
#   2. 2 tiles at many samples, one task cancelled mid-render with scancel:
#      merge refuses the interrupted piece; `sbatch --array=K` resumes it
#      from its checkpoint and the merge is byte-identical again;
#   3. frames 0..5 as an array of 3 tasks of 2 frames, each frame
#      byte-identical to a single-process render of that frame.
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$PWD"
export PATH="$PATH:/usr/sbin:/sbin"

say() { printf 'slurm [%3ss] %s\n' "$SECONDS" "$*"; }
fail() {
  say "FAILED: $*" >&2
  exit 1
}

# The doc shows the batch scripts verbatim, so that what runs here is what
# it tells users to run.
for script in docs/farm/*.sbatch; do
  python3 - "$script" <<'PY' || fail "docs/distributed.md does not show $script as it is"
import sys
script = open(sys.argv[1]).read()
doc = open("docs/distributed.md").read()
sys.exit(0 if "```bash\n" + script + "```\n" in doc else 1)
PY
done
say "docs/distributed.md shows docs/farm/*.sbatch verbatim"

skip() {
  echo "slurm: $*" >&2
  # In CI the recipe must run; elsewhere skipping is allowed.
  [ -n "${CI:-}" ] && exit 1
  exit 0
}
# slurmd must run as root to start the jobs.
[ "$(id -u)" = 0 ] || skip "the test cluster needs root"
tools=(munged mungekey slurmctld slurmd sbatch squeue scancel sinfo sacct)
have_tools() {
  for t in "${tools[@]}"; do command -v "$t" >/dev/null || return 1; done
}
if ! have_tools; then
  apt=(env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends slurm-wlm munge)
  "${apt[@]}" >/dev/null || { apt-get update >/dev/null && "${apt[@]}" >/dev/null; } || true
fi
have_tools || skip "slurm-wlm and munge are not installed and cannot be installed here"
cargo build --release --quiet
rt="$repo/target/release/rtlang"
scene="$repo/tests/dist_support/moving.rt"

scratch="$(mktemp -d "${TMPDIR:-/tmp}/rtlang-slurm.XXXXXX")"
# munged wants every directory above its socket searchable by all.
chmod 755 "$scratch"
export SLURM_CONF="$scratch/slurm.conf"

stop_daemons() { # pid files: SIGTERM to all at once, SIGKILL after 10 s
  local pids=() pid alive
  for f in "$@"; do
    [ -s "$f" ] && pids+=("$(cat "$f")")
  done
  [ "${#pids[@]}" = 0 ] && return 0
  kill "${pids[@]}" 2>/dev/null || true
  for _ in $(seq 100); do
    alive=0
    for pid in "${pids[@]}"; do
      kill -0 "$pid" 2>/dev/null && alive=1
    done
    [ "$alive" = 0 ] && return 0
    sleep 0.1
  done
  kill -9 "${pids[@]}" 2>/dev/null || true
}
cleanup() {
  local status=$?
  trap - EXIT
  if [ "$status" != 0 ] && [ -d "$scratch/log" ]; then
    for f in "$scratch"/log/*.log "$scratch"/work/*.out; do
      [ -f "$f" ] || continue
      echo "--- last lines of ${f#"$scratch"/}" >&2
      tail -n 20 "$f" >&2
    done
  fi
  if [ -s "$scratch/slurmctld.pid" ]; then
    left="$(squeue -h -o %A 2>/dev/null || true)"
    if [ -n "$left" ]; then
      # shellcheck disable=SC2086 # one job id per word
      scancel $left 2>/dev/null || true
      for _ in $(seq 100); do
        [ -z "$(squeue -h -o %A 2>/dev/null || true)" ] && break
        sleep 0.2
      done
    fi
  fi
  stop_daemons "$scratch"/{slurmd,slurmctld,munged}.pid
  rm -rf "$scratch"
  say "daemons stopped, scratch directory removed"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# munged with its own key and socket.
mungekey --create --keyfile="$scratch/munge.key"
munged --socket="$scratch/munge.sock" --key-file="$scratch/munge.key" \
  --pid-file="$scratch/munged.pid" --log-file="$scratch/munged.log" \
  --seed-file="$scratch/munged.seed"

# slurmctld and slurmd on free ports of the loopback interface; the node line
# is what slurmd finds on this machine.
mkdir -p "$scratch/state" "$scratch/spool" "$scratch/log" "$scratch/work"
host="$(hostname -s)"
node="$(slurmd -C | grep '^NodeName=')"
read -r ctld_port slurmd_port < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks:
    s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))')
cat >"$SLURM_CONF" <<EOF
ClusterName=rtlang
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$scratch/munge.sock
StateSaveLocation=$scratch/state
SlurmdSpoolDir=$scratch/spool
SlurmctldPidFile=$scratch/slurmctld.pid
SlurmdPidFile=$scratch/slurmd.pid
SlurmctldLogFile=$scratch/log/slurmctld.log
SlurmdLogFile=$scratch/log/slurmd.log
# No cgroups: processes are tracked through /proc and not confined.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
# No slurmdbd: finished jobs stay visible to squeue for MinJobAge seconds,
# and the completion records go to a text file that sacct --completion reads.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$scratch/log/jobcomp.txt
MinJobAge=600
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
# Look at the queue every second rather than every minute.
SchedulerParameters=sched_interval=1
ReturnToService=2
KillWait=10
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld
slurmd
for _ in $(seq 150); do
  [ "$(sinfo -h -n "$host" -o %T 2>/dev/null)" = idle ] && break
  sleep 0.2
done
[ "$(sinfo -h -n "$host" -o %T)" = idle ] || fail "node $host did not come up: $(sinfo -h -n "$host" -o '%T %E')"
say "cluster up ($(sinfo --version), $(munged --version 2>&1 | head -n 1)): $(sinfo -h -o '%P %D node %T, %c CPUs, %m MB')"

# The scripts' paths and sample counts come from the environment; the sizes
# from the command line, which overrides the scripts' #SBATCH lines.
export RTLANG="$rt" SCENE="$scene" MEMORY_BUDGET=0.5
small=(--cpus-per-task=1 --mem=1G --time=10)
work="$scratch/work"
cd "$work"

wait_jobs() { # job ids: wait until none is pending or running
  local deadline=$((SECONDS + 300))
  while [ -n "$(squeue -h -j "$(IFS=,; echo "$*")" -o %i)" ]; do
    [ "$SECONDS" -lt "$deadline" ] || fail "jobs $* still queued after 300 s"
    sleep 0.2
  done
}
check_completed() { # job id, number of tasks: every task COMPLETED
  local states ids records
  states="$(squeue -h -t all -j "$1" -o '%i %T' | sort -V)"
  [ "$(grep -c ' COMPLETED$' <<<"$states")" = "$2" ] || fail "job $1: $(tr '\n' ' ' <<<"$states")"
  # sacct without slurmdbd reads the completion file, where each task is a
  # job of its own (%A); Slurm 22.05 warns there about the array fields.
  ids="$(squeue -h -t all -j "$1" -o %A | paste -sd,)"
  records="$(sacct --completion -n -j "$ids" -o State 2>/dev/null | grep -c COMPLETED)"
  [ "$records" = "$2" ] || fail "job $1: sacct --completion finds $records COMPLETED of $2"
  say "job $1: all $2 tasks COMPLETED (squeue; sacct --completion agrees)"
}

# 1. Tiles × passes, merged by a dependent job, as the doc submits them.
say "1. 4 tiles x 2 passes of $(basename "$scene") at 8 spp, and a dependent merge"
export OUT="$work/pieces" TILES=4 SPP=8
jobid=$(sbatch --parsable --array=0-7 "${small[@]}" "$repo/docs/farm/render.sbatch")
mergeid=$(sbatch --parsable --dependency=afterok:"$jobid" --job-name=rt-merge \
  --output=%x-%j.out "${small[@]}" \
  --wrap "\"$rt\" merge $OUT/t*-p*.exr --average -o $work/frame.exr")
say "submitted array job $jobid (tasks 0-7) and merge job $mergeid"
wait_jobs "$jobid"
check_completed "$jobid" 8
wait_jobs "$mergeid"
check_completed "$mergeid" 1
say "log of task ${jobid}_0, rt-tiles-${jobid}_0.out:"
sed 's/^/    /' "rt-tiles-${jobid}_0.out"
say "log of the merge job: $(cat "rt-merge-$mergeid.out")"
"$rt" merge "$OUT"/t*-p0.exr -o pass0.exr 2>/dev/null
"$rt" render "$SCENE" --spp 8 --sidecar --quiet -o single-p0.exr 2>/dev/null
"$rt" render "$SCENE" --spp 8 --pass 1 --quiet -o single-p1.exr 2>/dev/null
cmp pass0.exr single-p0.exr
say "pass 0's 4 tiles merge byte-identical to the single-process render"
"$rt" merge --average single-p0.exr single-p1.exr -o single-avg.exr 2>/dev/null
cmp frame.exr single-avg.exr
say "the merge job's 2-pass average is byte-identical to the single-process passes averaged"

# 2. A task cancelled mid-render and submitted again on its own. A tile
# takes seconds at this many samples; Slurm took 0.1 to 0.5 s from scancel
# to the task's SIGTERM here.
export OUT="$work/slow" TILES=2 SPP=32768
say "2. 2 tiles at $SPP spp; task 1 cancelled once it has started rendering"
jobid=$(sbatch --parsable --array=0-1 "${small[@]}" "$repo/docs/farm/render.sbatch")
log="rt-tiles-${jobid}_1.out"
deadline=$((SECONDS + 120))
until grep -q '^{"event":"tile"' "$log" 2>/dev/null; do
  [ "$SECONDS" -lt "$deadline" ] || fail "task ${jobid}_1 printed no progress in 120 s"
  sleep 0.05
done
scancel "${jobid}_1"
say "scancel ${jobid}_1 after its first progress line"
wait_jobs "$jobid"
states="$(squeue -h -t all -j "$jobid" -o '%i %T' | sort -V | tr '\n' ' ')"
[ "$states" = "${jobid}_0 COMPLETED ${jobid}_1 CANCELLED " ] || fail "job $jobid: $states"
say "job $jobid: $states"
say "the cancelled task's log ends:"
grep -v '^{"event":"tile"' "$log" | sed 's/^/    /'
reached="$(python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); print(d["spp_reached"], d["spp"])' "$OUT/t2-p0.exr.json")"
[ "${reached% *}" -lt "${reached#* }" ] || fail "the cancelled tile is complete ($reached)"
if "$rt" merge "$OUT"/t*-p0.exr -o slow.exr 2>merge.err; then
  fail "merge accepted the interrupted tile"
fi
say "merge refuses: $(awk '/×/ { on = 1 } /help:/ { on = 0 } on' merge.err | sed 's/^ *[×│]* *//' | tr '\n' ' ')"
[ -f "$OUT/t2-p0.ckpt" ] || fail "the cancelled task left no checkpoint"
again=$(sbatch --parsable --array=1 "${small[@]}" "$repo/docs/farm/render.sbatch")
say "sbatch --array=1: job $again"
wait_jobs "$again"
check_completed "$again" 1
done_at() { # log, event: samples_done of the first line of that event
  python3 -c '
import json, sys
for line in open(sys.argv[1]):
    if line.startswith("{") and json.loads(line)["event"] == sys.argv[2]:
        print(json.loads(line)["samples_done"])
        break' "$@"
}
stopped=$(done_at "$log" interrupted)
resumed=$(done_at "rt-tiles-${again}_1.out" tile)
[ "$resumed" -ge "$stopped" ] || fail "task ${again}_1 started at $resumed samples, not from the checkpoint's $stopped"
say "it resumed from the checkpoint: first progress line at samples_done $resumed; the cancelled run had reached $stopped"
"$rt" merge "$OUT"/t*-p0.exr -o slow.exr 2>/dev/null
"$rt" render "$SCENE" --spp "$SPP" --quiet -o single-slow.exr 2>/dev/null
cmp slow.exr single-slow.exr
say "the merge is byte-identical to the single-process render at $SPP spp"

# 3. An animation: frames 0..5, two frames per task.
say "3. frames 0..5 at 8 spp, 2 frames per task"
export OUT="$work/frames" SPP=8
jobid=$(sbatch --parsable --array=0-5:2 "${small[@]}" "$repo/docs/farm/frames.sbatch")
wait_jobs "$jobid"
check_completed "$jobid" 3
for f in 0 1 2 3 4 5; do
  "$rt" render "$SCENE" --frame "$f" --spp 8 --quiet -o "single.$f.exr" 2>/dev/null
  cmp "$OUT/shot.000$f.exr" "single.$f.exr"
done
say "every frame is byte-identical to a single-process render of that frame"
say "passed"
