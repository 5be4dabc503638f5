#!/usr/bin/env bash
# Run a command with a throwaway PostgreSQL server for the hub's database tests:
#   bash scripts/with-postgres.sh cargo test -p hub
# Creates a cluster in a temp dir (initdb, trust auth, listening on 127.0.0.1 on a free port
# and on a unix socket in the temp dir), exports
#   TELEREHAB_TEST_PG_URL=postgres://postgres@127.0.0.1:PORT/postgres
# runs the command, then stops the server and removes the cluster (also on failure or ^C).
# Run as root, the server runs as the `postgres` OS user (initdb refuses root).
# If the server cannot start, prints `SKIPPED: postgres could not start: <reason>` and still
# runs the command, without the variable (the Postgres tests then skip with a message).
# The exit status is the command's. TELEREHAB_PG_BINDIR overrides where initdb and pg_ctl are.
set -uo pipefail

if [ $# -eq 0 ]; then
  echo "usage: $0 CMD [ARGS...]" >&2
  exit 2
fi

skip() {
  echo "SKIPPED: postgres could not start: $1" >&2
  shift
  unset TELEREHAB_TEST_PG_URL
  "$@"
}

start_and_run() {
  local bindir
  bindir="${TELEREHAB_PG_BINDIR:-$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)}"
  if [ -z "$bindir" ] || [ ! -x "$bindir/initdb" ]; then
    echo "no initdb under /usr/lib/postgresql/*/bin (scripts/setup.sh installs postgresql)"
    return 3
  fi
  PGTMP="$(mktemp -d /tmp/telerehab-pg.XXXXXX)" || return 3
  local as=()
  if [ "$(id -u)" -eq 0 ]; then
    if ! id postgres >/dev/null 2>&1; then
      echo "running as root but there is no 'postgres' OS user to run the server as"
      return 3
    fi
    chown postgres: "$PGTMP"
    as=(runuser -u postgres --)
  fi
  chmod 700 "$PGTMP"
  local port
  port="$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')" \
    || { echo "cannot find a free port"; return 3; }
  if ! "${as[@]}" "$bindir/initdb" -D "$PGTMP/data" -U postgres --auth=trust -E UTF8 \
      --no-sync >"$PGTMP/initdb.log" 2>&1; then
    tail -n 5 "$PGTMP/initdb.log"
    return 3
  fi
  if ! "${as[@]}" "$bindir/pg_ctl" -D "$PGTMP/data" -l "$PGTMP/server.log" -w -t 30 \
      -o "-c listen_addresses=127.0.0.1 -p $port -k $PGTMP -c fsync=off -c max_connections=200" \
      start >/dev/null 2>&1; then
    tail -n 5 "$PGTMP/server.log" 2>/dev/null
    return 3
  fi
  PGCTL=("${as[@]}" "$bindir/pg_ctl" -D "$PGTMP/data")
  export TELEREHAB_TEST_PG_URL="postgres://postgres@127.0.0.1:$port/postgres"
  echo "with-postgres: PostgreSQL $("$bindir/postgres" --version | awk '{print $3}') on 127.0.0.1:$port (socket dir $PGTMP)"
  return 0
}

cleanup() {
  if [ -n "${PGCTL+x}" ]; then
    "${PGCTL[@]}" stop -m fast >/dev/null 2>&1 || true
  fi
  if [ -n "${PGTMP:-}" ] && [ -d "$PGTMP" ]; then
    rm -rf "$PGTMP"
  fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# Called in this shell (a redirection does not fork) so PGTMP, PGCTL and the URL persist.
START_LOG="$(mktemp /tmp/telerehab-pg-start.XXXXXX.log)"
if start_and_run >"$START_LOG" 2>&1; then
  grep '^with-postgres:' "$START_LOG" >&2 || true
  rm -f "$START_LOG"
  "$@"
else
  reason="$(grep -v '^with-postgres:' "$START_LOG" | tr '\n' ' ' | sed 's/ *$//')"
  rm -f "$START_LOG"
  cleanup
  unset PGCTL PGTMP
  skip "${reason:-unknown reason}" "$@"
fi
