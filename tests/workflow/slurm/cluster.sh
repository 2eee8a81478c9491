#!/usr/bin/env bash
# A real one-node SLURM cluster on this machine, for testing the workflow's SLURM profiles:
# munge + slurmctld + slurmd, with accounting (slurmdbd backed by a MariaDB server of its own,
# so `sacct` answers, as Snakemake's SLURM executor plugin needs) from Debian's packages,
# loopback only, all state in a scratch folder. The cluster has an account, granudrag, of which
# the user running the jobs (root) is a member. Runs as root (the daemons need it).
#   cluster.sh start DIR    installs the packages if missing, writes DIR/slurm.conf and
#                           DIR/slurmdbd.conf, starts the database and the daemons and waits
#                           until the node takes jobs; prints "export SLURM_CONF=DIR/slurm.conf"
#   cluster.sh stop DIR     stops the daemons started by `start DIR`
set -euo pipefail
cmd=${1:?usage: cluster.sh start|stop DIR}
dir=$(realpath -m "${2:?usage: cluster.sh start|stop DIR}")
node=$(hostname -s)

start() {
  [ "$(id -u)" -eq 0 ] || { echo "cluster.sh: the SLURM daemons need root" >&2; exit 2; }
  local missing=()
  for p in slurmctld slurmd slurm-client slurmdbd munge mariadb-server; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  fi
  mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
  chmod 700 "$dir/munge"
  # munge: its own key and socket in DIR, so nothing of the machine's is touched.
  [ -f "$dir/munge/munge.key" ] || dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/seed"
  # The accounting database: a MariaDB server of its own (TCP on loopback, port 16306), a
  # database user for slurmdbd.
  mkdir -p "$dir/mysql"
  if [ ! -d "$dir/mysql/data/mysql" ]; then
    mariadb-install-db --user=root --datadir="$dir/mysql/data" --skip-test-db \
      --auth-root-authentication-method=socket > "$dir/mysql/install.log" 2>&1 \
      || { echo "cluster.sh: mariadb-install-db failed:" >&2; tail -5 "$dir/mysql/install.log" >&2; exit 1; }
  fi
  mariadbd --no-defaults --user=root --datadir="$dir/mysql/data" --socket="$dir/mysql/mysql.sock" \
    --pid-file="$dir/mysql/mariadbd.pid" --bind-address=127.0.0.1 --port=16306 \
    --log-error="$dir/mysql/mariadbd.log" --innodb-buffer-pool-size=64M \
    --innodb-lock-wait-timeout=900 --max-connections=50 >> "$dir/mysql/mariadbd.log" 2>&1 < /dev/null &
  local ok=""
  for _ in $(seq 600); do
    mariadb --no-defaults --socket="$dir/mysql/mysql.sock" -u root -e 'SELECT 1' >/dev/null 2>&1 && { ok=1; break; }
    sleep 0.1
  done
  [ -n "$ok" ] || { echo "cluster.sh: MariaDB did not start:" >&2; tail -5 "$dir/mysql/mariadbd.log" >&2; exit 1; }
  mariadb --no-defaults --socket="$dir/mysql/mysql.sock" -u root <<'SQL'
CREATE USER IF NOT EXISTS 'slurm'@'127.0.0.1' IDENTIFIED BY 'granudrag-test';
GRANT ALL ON slurm_acct_db.* TO 'slurm'@'127.0.0.1';
FLUSH PRIVILEGES;
SQL
  cat > "$dir/slurmdbd.conf" <<CONF
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
DbdHost=localhost
DbdAddr=127.0.0.1
DbdPort=16819
SlurmUser=root
PidFile=$dir/slurmdbd.pid
LogFile=$dir/slurmdbd.log
StorageType=accounting_storage/mysql
StorageHost=127.0.0.1
StoragePort=16306
StorageUser=slurm
StoragePass=granudrag-test
StorageLoc=slurm_acct_db
CONF
  chmod 600 "$dir/slurmdbd.conf"
  local cpus mem
  cpus=$(nproc)
  mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 1024 ))
  cat > "$dir/slurm.conf" <<CONF
ClusterName=granudrag-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=127.0.0.1
AccountingStoragePort=16819
AccountingStoragePass=$dir/munge/munge.socket
JobAcctGatherType=jobacct_gather/linux
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SlurmdTimeout=60
# A job past its time limit is killed 5 s after SIGTERM (the time-limit test waits less).
KillWait=5
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir/slurm.conf"
  # slurmdbd reads slurmdbd.conf beside $SLURM_CONF; the cluster, its account and user are
  # registered before slurmctld starts.
  slurmdbd
  ok=""
  for _ in $(seq 300); do
    sacctmgr -n list cluster >/dev/null 2>&1 && { ok=1; break; }
    sleep 0.2
  done
  [ -n "$ok" ] || { echo "cluster.sh: slurmdbd did not answer:" >&2; tail -5 "$dir/slurmdbd.log" >&2; exit 1; }
  sacctmgr -i add cluster granudrag-test >/dev/null
  sacctmgr -i add account granudrag cluster=granudrag-test description=test organization=test >/dev/null
  sacctmgr -i add user root account=granudrag cluster=granudrag-test >/dev/null
  slurmctld -f "$SLURM_CONF"
  slurmd -f "$SLURM_CONF"
  # Until the node takes jobs: seconds on an idle machine; 300 s only bounds a node that never does.
  for _ in $(seq 300); do
    if sinfo -h -o %t 2>/dev/null | grep -qE "^(idle|mix|alloc)"; then
      echo "export SLURM_CONF=$SLURM_CONF"
      return 0
    fi
    sleep 1
  done
  echo "cluster.sh: the node did not come up; logs in $dir" >&2
  tail -5 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 || true
  exit 1
}

stop() {
  local pids=() pid
  for pidfile in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/slurmdbd.pid" "$dir/mysql/mariadbd.pid" \
                 "$dir/munge/munged.pid"; do
    [ -f "$pidfile" ] || continue
    pid=$(cat "$pidfile")
    kill "$pid" 2>/dev/null && pids+=("$pid")
  done
  # Until the daemons have exited (their ports free for the next cluster), at most 60 s.
  for _ in $(seq 600); do
    pid=""
    for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && pid=$p; done
    [ -z "$pid" ] && return 0
    sleep 0.1
  done
}

case "$cmd" in
  start) start ;;
  stop) stop ;;
  *) echo "usage: cluster.sh start|stop DIR" >&2; exit 2 ;;
esac
