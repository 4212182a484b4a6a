#!/usr/bin/env bash
# The cluster recipes of the README, run by a real Slurm: a one-node Slurm (munged, slurmctld,
# slurmd) is started here on this machine, the job scripts of examples/slurm/ are submitted with
# sbatch, and what they promise is asserted:
#   1. a job array of 4 shards, merged, gives the unsharded comparison's runs.csv (runtimes aside);
#   2. a shard stopped by its time limit saves its runs under way and marks the others not_run;
#      submitting it again completes it (--resume-missing) and merge accepts it;
#   3. an MLS run requeued by Slurm continues from its checkpoint to the same packing, byte for
#      byte, as an uninterrupted run.
# Needs root (to install Debian's slurm-wlm and munge when missing, and to run the daemons);
# skipped with a message where Slurm cannot be installed, except under CI (the environment
# variable CI set), where that is a failure. Prints "slurm: P passed, F failed".
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
EXAMPLES="$ROOT/examples/slurm"

# skip REASON: the suite cannot run here; a failure under CI, which must run it.
skip() {
    if [ -n "${CI+set}" ]; then
        echo "slurm: FAILED: CI is set but the suite cannot run: $*"
        exit 1
    fi
    echo "slurm: skipped: $*"
    exit 0
}

# --- Slurm and munge ---------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null ||
    ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    [ "$(id -u)" = 0 ] || skip "Slurm is not installed and installing it needs root"
    command -v apt-get >/dev/null || skip "Slurm is not installed and there is no apt-get"
    echo "slurm: installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null || skip "apt-get update failed"
    apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null ||
        skip "apt-get install slurm-wlm munge failed"
fi
[ "$(id -u)" = 0 ] || skip "slurmd must run as root to start jobs"

# --- the binary under test ---------------------------------------------------------------------
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
# The cargo profile of the test build (scripts/test-all), whose binary is reused when present.
PROFILE="${PACKBENCH_TEST_PROFILE:-release-tests}"
if [ ! -x "$TARGET/$PROFILE/packbench" ]; then
    echo "slurm: building packbench (cargo build --profile $PROFILE)"
    (cd "$ROOT" && cargo build --profile "$PROFILE" -q -p packbench --bin packbench)
fi
export PATH="$TARGET/$PROFILE:$PATH"

# --- a one-node Slurm in a temporary folder ----------------------------------------------------
WORK=$(mktemp -d /tmp/packbench-slurm.XXXXXX)
chmod 755 "$WORK" # munged wants its socket's folder searchable by all
SLURM_DIR="$WORK/slurm"
mkdir -p "$SLURM_DIR/state" "$SLURM_DIR/spool"
PIDS=()
KEEP_WORK=0

stop_slurm() {
    set +e
    if [ -f "$SLURM_DIR/slurm.conf" ] && [ "${#PIDS[@]}" -gt 0 ]; then
        scancel --quiet --user=root >/dev/null 2>&1 # SLURM_CONF: this Slurm's jobs only
        for _ in $(seq 1 20); do
            [ -z "$(squeue -h 2>/dev/null)" ] && break
            sleep 0.5
        done
    fi
    # Daemons last started stop first: slurmd, slurmctld, munged.
    for ((k = ${#PIDS[@]} - 1; k >= 0; k--)); do
        kill "${PIDS[k]}" 2>/dev/null
    done
    for pid in "${PIDS[@]}"; do
        for _ in $(seq 1 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.1
        done
        kill -KILL "$pid" 2>/dev/null
    done
    if [ "$KEEP_WORK" = 1 ]; then
        echo "slurm: logs kept in $WORK"
    else
        rm -rf "$WORK"
    fi
}
trap stop_slurm EXIT

# A TCP port nobody listens on.
free_port() {
    local p
    for _ in $(seq 1 50); do
        p=$((20000 + RANDOM % 20000))
        if ! (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null; then
            echo "$p"
            return
        fi
    done
    return 1
}
CTLD_PORT=$(free_port)
SLURMD_PORT=$(free_port)
[ "$CTLD_PORT" != "$SLURMD_PORT" ] || SLURMD_PORT=$((CTLD_PORT + 1))

HOST=$(hostname -s)
dd if=/dev/urandom of="$SLURM_DIR/munge.key" bs=1024 count=1 status=none
chmod 400 "$SLURM_DIR/munge.key"

# No cgroups (proctrack/linuxproc, task/none): works in a container; jobs are tracked by their
# process tree. jobcomp/filetxt keeps state, elapsed time and exit code of every job for
# `sacct --completion` without a database. KillWait: seconds from SIGTERM to SIGKILL.
cat >"$SLURM_DIR/slurm.conf" <<EOF
ClusterName=packbench-test
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$SLURM_DIR/munge.socket,cred_expire=10
CredType=cred/munge
StateSaveLocation=$SLURM_DIR/state
SlurmdSpoolDir=$SLURM_DIR/spool
SlurmctldPidFile=$SLURM_DIR/slurmctld.pid
SlurmdPidFile=$SLURM_DIR/slurmd.pid
SlurmctldLogFile=$SLURM_DIR/slurmctld.log
SlurmdLogFile=$SLURM_DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$SLURM_DIR/jobcomp.txt
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
KillWait=10
MinJobAge=600
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=short Nodes=$HOST Default=YES MaxTime=15 State=UP
EOF
export SLURM_CONF="$SLURM_DIR/slurm.conf"

munged --foreground --force --socket="$SLURM_DIR/munge.socket" --key-file="$SLURM_DIR/munge.key" \
    --pid-file="$SLURM_DIR/munged.pid" --log-file="$SLURM_DIR/munged.log" \
    --seed-file="$SLURM_DIR/munged.seed" >"$SLURM_DIR/munged.out" 2>&1 &
PIDS+=($!)
for _ in $(seq 1 50); do
    [ -S "$SLURM_DIR/munge.socket" ] && break
    sleep 0.1
done
slurmctld -D -c -f "$SLURM_CONF" >"$SLURM_DIR/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -f "$SLURM_CONF" >"$SLURM_DIR/slurmd.out" 2>&1 &
PIDS+=($!)

node_state() { sinfo -h -N -o %T 2>/dev/null || true; }
for _ in $(seq 1 60); do
    [ "$(node_state)" = idle ] && break
    sleep 0.5
done
if [ "$(node_state)" != idle ]; then
    KEEP_WORK=1
    tail -n 20 "$SLURM_DIR"/slurmctld.log "$SLURM_DIR"/slurmd.log 2>/dev/null || true
    echo "slurm: the node did not come up (state: '$(node_state)'); 1 failed"
    exit 1
fi
echo "slurm: one-node Slurm $(sinfo -V | cut -d' ' -f2) up on $HOST (2 CPUs)"

# --- helpers -----------------------------------------------------------------------------------
# From here on a failed command is a failed check, not the end of the suite.
set +e
PASSED=0
FAILED=0
FAILURES=()
declare -A FAILS
# fail CHECK MESSAGE: records a failure of CHECK.
fail() {
    FAILS[$1]=$((${FAILS[$1]:-0} + 1))
    FAILURES+=("$1: $2")
    echo "slurm: FAIL $1: $2"
}
# result CHECK SUMMARY: CHECK passed unless fail CHECK was called.
result() {
    if [ "${FAILS[$1]:-0}" = 0 ]; then
        PASSED=$((PASSED + 1))
        echo "slurm: ok   $1: $2"
    else
        FAILED=$((FAILED + 1))
    fi
}

# Jobs (or array tasks) of the given ids that Slurm still lists.
listed() { squeue -h -j "$(
    IFS=,
    echo "$*"
)" -o %i 2>/dev/null || true; }
# wait_jobs SECONDS ID...: waits until Slurm lists none of the jobs; false on timeout.
wait_jobs() {
    local limit=$1
    shift
    local t0=$SECONDS
    while [ -n "$(listed "$@")" ]; do
        [ $((SECONDS - t0)) -lt "$limit" ] || return 1
        sleep 1
    done
}
# The column NAME of runs.csv in folder DIR, one value per row (the first 14 columns hold no
# commas).
column() {
    awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
        { print $c }' "$1/runs.csv"
}
# runs.csv of DIR without its runtime_s column.
without_runtime() { cut -d, -f1-11,13- "$1/runs.csv"; }
count() { grep -c -x "$1" || true; }

# The job scripts are used as written in examples/slurm/ and shown verbatim in README.md.
for script in "$EXAMPLES"/*.sbatch; do
    awk -v f="$script" 'BEGIN { while ((getline l < f) > 0) s = s l "\n" }
        { r = r $0 "\n" } END { exit index(r, s) ? 0 : 1 }' "$ROOT/README.md" ||
        fail readme "README.md does not show $(basename "$script") verbatim"
done
result readme "README.md shows each job script of examples/slurm/ verbatim"

# --- submit everything; the node runs two jobs at a time -----------------------------------------
cd "$WORK"
mkdir -p array limit mls-requeued mls-whole
(cd limit && sbatch --parsable "$EXAMPLES/compare-time-limit.sbatch") >"$WORK/limit.id"
(cd mls-requeued && sbatch --parsable "$EXAMPLES/mls-requeue.sbatch") >"$WORK/rq.id"
(cd array && sbatch --parsable "$EXAMPLES/compare-array.sbatch") >"$WORK/array.id"
(cd mls-whole && sbatch --parsable "$EXAMPLES/mls-requeue.sbatch") >"$WORK/whole.id"
LIMIT=$(<"$WORK/limit.id")
RQ=$(<"$WORK/rq.id")
ARRAY=$(<"$WORK/array.id")
WHOLE=$(<"$WORK/whole.id")
echo "slurm: submitted time-limit array $LIMIT, MLS $RQ (to requeue), shard array $ARRAY, MLS $WHOLE"

# --- 3 (first half). Requeue the MLS run once it is well under way ------------------------------
t0=$SECONDS
until [ "$(cat mls-requeued/mls.log 2>/dev/null | grep -c '^step ')" -ge 3 ]; do
    if [ $((SECONDS - t0)) -gt 600 ] || [ -z "$(listed "$RQ")" ]; then
        fail requeue "MLS job $RQ ended or showed no progress before it could be requeued"
        break
    fi
    sleep 0.5
done
if [ "${FAILS[requeue]:-0}" = 0 ]; then
    # The requeued job waits cred_expire + 1 s (10 s here, AuthInfo above) before it may start
    # again: until then the node refuses its revoked credential. Forcing StartTime=now raced it.
    scontrol requeue "$RQ"
    echo "slurm: requeued MLS job $RQ"
fi

# --- 1. The shard array against the unsharded comparison ----------------------------------------
mkdir -p whole
(cd whole && packbench compare --Ndim 2 --N 24 --methods adam,fire,ls --seeds 8 --seed 1 \
    --jobs 1 --quiet --out out) 2>/dev/null
if ! wait_jobs 900 "$ARRAY"; then
    fail array "the shard array $ARRAY did not finish in 900 s"
else
    packbench merge array/shards/* --out array/merged 2>"$WORK/merge-array.err" ||
        fail array "merge failed: $(cat "$WORK/merge-array.err")"
    rows=$(($(wc -l <whole/out/runs.csv) - 1))
    [ "$rows" = 24 ] || fail array "the unsharded comparison has $rows rows, not 24"
    if ! diff <(without_runtime whole/out) <(without_runtime array/merged) >"$WORK/array.diff"; then
        fail array "merged shards differ from the unsharded run: $(head -c 2000 "$WORK/array.diff")"
    fi
    [ "$(column array/merged termination | count not_run)" = 0 ] ||
        fail array "the merged shards hold not_run rows"
fi
result array "4 shards by sbatch --array, merged, equal the unsharded runs.csv (24 runs, runtimes aside)"

# --- 2. The shard stopped by its time limit -----------------------------------------------------
interrupted=0
not_run=0
if ! wait_jobs 900 "$LIMIT"; then
    fail time-limit "the time-limited array $LIMIT did not end in 900 s"
else
    stopped=limit/time-limited/1
    cp "$stopped/runs.csv" "$WORK/stopped.csv" 2>/dev/null ||
        fail time-limit "the stopped shard wrote no runs.csv"
    terms=$(column "$stopped" termination)
    interrupted=$(count interrupted <<<"$terms")
    not_run=$(count not_run <<<"$terms")
    echo "slurm: the time limit left shard 1: $(tr '\n' ' ' <<<"$terms")"
    # The signal ended the job before its limit, packbench writing its outputs.
    state=$(sacct --completion -n -P -j "$LIMIT" -o State 2>/dev/null | head -n 1)
    [ "$state" = COMPLETED ] || fail time-limit "the stopped shard's job ended $state, not COMPLETED"
    # One run at a time (SLURM_CPUS_PER_TASK=1 sets --jobs): the run under way is interrupted,
    # every later one not_run.
    [ "$interrupted" = 1 ] || fail time-limit "$interrupted interrupted runs, not 1"
    [ "$not_run" -ge 1 ] || fail time-limit "no not_run rows: the time limit came after the runs"
    while IFS=, read -r method seed term phi; do
        if [ "$term" = interrupted ]; then
            [ -n "$phi" ] || fail time-limit "the interrupted $method seed $seed has no φ"
            [ -s "$stopped/packings/${method}_seed$seed.txt" ] ||
                fail time-limit "the interrupted $method seed $seed saved no packing"
        fi
    done < <(paste -d, <(column "$stopped" method) <(column "$stopped" seed) \
        <(column "$stopped" termination) <(column "$stopped" phi))
    # Shard 2 (fire, fast) holds its 10 rows, finished or not: how many finish inside the
    # limit depends on the node's load, so it is not asserted; the rerun completes them.
    [ "$(column limit/time-limited/2 termination | grep -c .)" = 10 ] ||
        fail time-limit "shard 2 (fire) did not write its 10 rows"
    # Again, both shards, with time to spare.
    AGAIN=$(cd limit && sbatch --parsable --array=1-2 --time=10 "$EXAMPLES/compare-time-limit.sbatch")
    if ! wait_jobs 900 "$AGAIN"; then
        fail time-limit "the rerun $AGAIN of the shards did not finish in 900 s"
    else
        terms=$(column "$stopped" termination; column limit/time-limited/2 termination)
        [ "$(grep -c -x 'not_run\|interrupted' <<<"$terms")" = 0 ] ||
            fail time-limit "the rerun left unfinished runs: $(tr '\n' ' ' <<<"$terms")"
        # The runs finished before the time limit were kept as they were (runtimes too).
        finished_before=$(awk -F, 'NR > 1 && $14 != "not_run" && $14 != "interrupted"' \
            "$WORK/stopped.csv" | cut -d, -f1-14)
        while IFS= read -r row; do
            [ -z "$row" ] || grep -qxF "$row" <(cut -d, -f1-14 "$stopped/runs.csv") ||
                fail time-limit "the finished run '$row' was not kept"
        done <<<"$finished_before"
        grep -q "($(grep -c . <<<"$finished_before" || true) kept from the earlier run)" \
            limit/time-limit-1.log || fail time-limit "the rerun did not keep the finished runs"
        if packbench merge limit/time-limited/1 limit/time-limited/2 --out limit/merged \
            2>"$WORK/merge-limit.err"; then
            rows=$(($(wc -l <limit/merged/runs.csv) - 1))
            [ "$rows" = 20 ] || fail time-limit "the merge holds $rows runs, not 20"
            ! grep -q unfinished "$WORK/merge-limit.err" ||
                fail time-limit "merge reports unfinished runs: $(cat "$WORK/merge-limit.err")"
        else
            fail time-limit "merge of the completed shard failed: $(cat "$WORK/merge-limit.err")"
        fi
    fi
fi
result time-limit "SIGTERM before the limit left $interrupted interrupted run (packing saved) and $not_run not_run; --resume-missing completed the shard; merge accepted it"

# --- 3. The requeued MLS run against the uninterrupted one --------------------------------------
if ! wait_jobs 900 "$RQ" "$WHOLE"; then
    fail requeue "the MLS jobs $RQ and $WHOLE did not finish in 900 s"
else
    grep -q "^packbench-mls: start 1 of job $RQ" mls-requeued/mls.log ||
        fail requeue "the requeued job did not start again (SLURM_RESTART_COUNT=1)"
    grep -q "checkpoint mls.checkpoint.json" mls-requeued/mls.log ||
        fail requeue "the stopped run wrote no checkpoint before it was requeued"
    [ -s mls-whole/mls.txt ] || fail requeue "the uninterrupted MLS run wrote no packing"
    if ! cmp -s mls-requeued/mls.txt mls-whole/mls.txt; then
        fail requeue "the requeued run's packing differs from the uninterrupted run's"
    fi
    grep -q "interrupted" mls-whole/mls.log &&
        fail requeue "the uninterrupted run was interrupted"
fi
result requeue "MLS job requeued by scontrol resumed from mls.checkpoint.json; mls.txt byte-identical to the uninterrupted run's"

# --- the jobs as Slurm recorded them -------------------------------------------------------------
echo "slurm: sacct --completion (jobcomp/filetxt):"
sacct --completion -o JobID%-6,JobName%-21,State,Start,Elapsed,ExitCode 2>/dev/null | sed 's/^/  /'

if [ "$FAILED" != 0 ]; then
    KEEP_WORK=1
    for f in "${FAILURES[@]}"; do echo "slurm: failure: $f"; done
fi
echo "slurm: $PASSED passed, $FAILED failed"
[ "$FAILED" = 0 ]
