#!/usr/bin/env bash
# The image's build stage on a checkout that has a build/ of its own (issue 14): the context
# docker/Dockerfile.dockerignore leaves must configure and build where the stage does it. No
# container engine here can pull debian:12, so the stage's steps run on this machine, on a
# context copied the way `docker build` copies it (patterns anchored at the context's root).
#   docker_context_test.sh SOURCE_DIR
set -euo pipefail
src=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "docker_context_test: FAIL: $*" >&2; exit 1; }

# A developer's checkout: the sources, and a build/ configured where they keep it.
mkdir "$work/host"
(cd "$src" && git ls-files -z --cached --others --exclude-standard |
  xargs -0 cp --parents -t "$work/host")
cmake -S "$work/host" -B "$work/host/build" -G Ninja >/dev/null
mv "$work/host" "$work/checkout"

# COPY . . with the ignore file, into the stage's own directory.
patterns="$work/patterns"
grep -v '^\s*#' "$src/docker/Dockerfile.dockerignore" | sed '/^\s*$/d' >"$patterns"
copy_context() {  # copy_context FROM TO [tar exclusion options...]
  local from=$1 to=$2
  shift 2
  mkdir -p "$to"
  (cd "$from" && tar "$@" -cf - $(ls -A)) | tar -C "$to" -xf -
}
copy_context "$work/checkout" "$work/src" --anchored --wildcards --exclude-from="$patterns"
[ ! -e "$work/src/build" ] || fail "the host's build/ is in the context"
[ -e "$work/src/CMakeLists.txt" ] || fail "the sources are not in the context"
[ -e "$work/src/docker/Dockerfile" ] || fail "docker/ is not in the context"

# The stage's configure and build (scripts/test's steps; one library, to stay quick).
cmake -S "$work/src" -B "$work/src/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configure failed"; }
cmake --build "$work/src/build" --target monocle_files >"$work/build.log" 2>&1 ||
  { cat "$work/build.log"; fail "build failed"; }

# Without the ignore file the same steps fail: the test can tell.
copy_context "$work/checkout" "$work/plain"
if cmake -S "$work/plain" -B "$work/plain/build" -G Ninja >"$work/plain.log" 2>&1; then
  fail "a context with the host's build/ configured: this test would not notice a bad ignore file"
fi
grep -q "is different" "$work/plain.log" || { cat "$work/plain.log"; fail "unexpected failure"; }
echo "docker_context_test: the context without build/ configures and builds; with it, it does not"
