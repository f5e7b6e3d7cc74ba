#!/usr/bin/env bash
# Builds the release binaries with the PTX embedded (swarf, the GPU test binary, the PTX test, the criterion
# bench), strips them and packs them into gpu-pack/ (git-ignored) with ci/gpu-run.sh, so that one device call
# runs everything on a GPU machine with no Rust toolchain:
#   ci/gpu-pack.sh && <device run, carry gpu-pack>: bash gpu-pack/gpu-run.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export SWARF_REQUIRE_PTX=1
pack=gpu-pack
rm -rf "$pack" && mkdir -p "$pack"

cargo build --release --bin swarf
cp "${CARGO_TARGET_DIR:-target}/release/swarf" "$pack/swarf"

# Test and bench executables, located through cargo's JSON messages.
exe() { python3 -c 'import json,sys
for l in sys.stdin:
    m = json.loads(l)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == sys.argv[1]:
        print(m["executable"])' "$1"; }
# SWARF_PACK_TESTS / SWARF_PACK_BENCHES choose fewer (the tree sent is limited to 64 MiB, carried run folders
# included).
# (suite: the CPU tests, whose stability_* modules the `hard` part runs on the GPU backend.)
for t in ${SWARF_PACK_TESTS-gpu ptx suite}; do
    f=$(cargo test --release --no-run --test "$t" --message-format=json 2>/dev/null | exe "$t" | tail -1)
    cp "$f" "$pack/test-$t"
done
for bn in ${SWARF_PACK_BENCHES-neighbours step mpm}; do
    f=$(cargo bench --no-run --bench "$bn" --message-format=json 2>/dev/null | exe "$bn" | tail -1)
    cp "$f" "$pack/bench-$bn"
done

shopt -s nullglob
bins=("$pack"/swarf "$pack"/test-* "$pack"/bench-*)
strip "${bins[@]}"
# Compressed: the tree sent to the device is limited to 64 MiB (gpu-run.sh unpacks).
gzip -9 "${bins[@]}"
cp ci/gpu-run.sh "$pack/gpu-run.sh"
# Earlier builds to compare with (parts firstrun, abfrom, abstep): SWARF_PACK_OLD names packed binaries
# (swarf-<name>.gz, e.g. kept from an earlier gpu-pack/swarf.gz), copied as they are.
for old in ${SWARF_PACK_OLD-}; do cp "$old" "$pack/"; done
git rev-parse --short HEAD > "$pack/COMMIT" 2>/dev/null || echo unknown > "$pack/COMMIT"
du -sh "$pack"
