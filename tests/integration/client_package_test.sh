#!/usr/bin/env bash
# Installs monocle from the build tree, builds client/examples as another project would
# (find_package(monocle)), starts monocled on its embedded default and runs the example
# against it.   Usage: client_package_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
src=$2
work=$(mktemp -d /tmp/monocle_client_package.XXXXXX)
monocled_pid=""
cleanup() {
  if [ -n "$monocled_pid" ]; then kill -TERM "$monocled_pid" 2>/dev/null || true; wait "$monocled_pid" || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

cmake --install "$build" --prefix "$work/prefix" >/dev/null
# A sanitizer build's library needs the same runtime in the program (scripts/test --sanitize).
cmake -S "$src/client/examples" -B "$work/example" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  "-DCMAKE_CXX_FLAGS=${MONOCLE_CXX_FLAGS:-}" "-DCMAKE_EXE_LINKER_FLAGS=${MONOCLE_LINKER_FLAGS:-}" >/dev/null
cmake --build "$work/example" >/dev/null

export CYCLONEDDS_URI="file://$src/docker/cyclonedds-loopback.xml"
"$work/prefix/bin/monocled" --domain 29 --state-dir "$work/state" 2>"$work/monocled.log" &
monocled_pid=$!
if ! "$work/example/monocle_client_example" --domain 29 --poses 3 >"$work/out.txt"; then
  echo "example failed; monocled log:"; cat "$work/monocled.log"; cat "$work/out.txt"; exit 1
fi
cat "$work/out.txt"
# The installed command line finds its library too.
"$work/prefix/bin/monocle" status --domain 29 --timeout 20 | tee "$work/status.txt"
grep -q "^sim-floor .*streaming" "$work/status.txt"
grep -q "^camera sim-corner (corner): streaming" "$work/out.txt"
test "$(grep -c '^pose frame' "$work/out.txt")" -ge 1
test "$(grep -c '^point x' "$work/out.txt")" -eq 2
kill -TERM "$monocled_pid"
wait "$monocled_pid"
monocled_pid=""
echo "client package test: ok"
