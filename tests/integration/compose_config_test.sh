#!/usr/bin/env bash
# docker/compose.yaml as Debian 12's Compose (docker-compose 1.29) reads it: `config` must
# accept it. The same file with a top-level `name:` (which Compose v2 takes and 1.29 refuses)
# must be refused, so that this test can tell.
#   compose_config_test.sh SOURCE_DIR
set -euo pipefail
src=$(cd "$1" && pwd)
if ! command -v docker-compose >/dev/null; then
  echo "compose_config_test: docker-compose is not installed (scripts/setup installs it); skipped"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "compose_config_test: FAIL: $*" >&2; exit 1; }

docker-compose -p monocle -f "$src/docker/compose.yaml" config -q ||
  fail "docker-compose $(docker-compose version --short) refuses docker/compose.yaml"
# The context and Dockerfile it names are found from the file's own directory.
# Read whole before grep -q looks: grep stops at its first match, and with pipefail the
# SIGPIPE that then meets docker-compose, still writing, failed this step at random.
resolved=$(docker-compose -p monocle -f "$src/docker/compose.yaml" config)
grep -q "dockerfile: docker/Dockerfile" <<<"$resolved" ||
  fail "the build's dockerfile is not docker/Dockerfile"
mkdir "$work/docker"
{ echo "name: monocle"; cat "$src/docker/compose.yaml"; } >"$work/docker/compose.yaml"
if docker-compose -f "$work/docker/compose.yaml" config -q 2>"$work/err"; then
  fail "a top-level name: was accepted: this test would not notice it"
fi
echo "compose_config_test: docker-compose $(docker-compose version --short) accepts docker/compose.yaml"
