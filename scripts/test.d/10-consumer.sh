# Another project takes gaussfilt by add_subdirectory() and, after
# cmake --install, by find_package(gaussfilt); both run the README example.
# Then both again with GF_SMALL's compact steps: forced through the
# subdirectory's option (GAUSSFILT_SMALL=ON), and by default in a library
# installed from a size-optimised build (MinSizeRel, GAUSSFILT_SMALL=AUTO).
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
want='mu = (4.0244, 1.2195)'
b=$GF_BUILD/consumer
rm -rf "$b"

cmake -S tests/consumer -B "$b/subdir" -DGAUSSFILT_SOURCE_DIR="$GF_ROOT" >/dev/null
cmake --build "$b/subdir" >/dev/null
out=$("$b/subdir/consumer")
grep -qF "$want" <<<"$out" || gf_die "add_subdirectory consumer printed: $out"
echo "add_subdirectory(): $(head -1 <<<"$out")"

cmake -S . -B "$b/lib" -DGAUSSFILT_BUILD_TESTS=OFF -DGAUSSFILT_BUILD_EXAMPLES=OFF \
    -DCMAKE_INSTALL_PREFIX="$b/prefix" >/dev/null
cmake --build "$b/lib" >/dev/null
cmake --install "$b/lib" >/dev/null
cmake -S tests/consumer -B "$b/pkg" -DCMAKE_PREFIX_PATH="$b/prefix" >/dev/null
cmake --build "$b/pkg" >/dev/null
out=$("$b/pkg/consumer")
grep -qF "$want" <<<"$out" || gf_die "find_package consumer printed: $out"
echo "find_package(gaussfilt): $(head -1 <<<"$out")"

# The same with GF_SMALL=1 (src/small.c's gf_kf2_update must be the one
# linked).
small_check() { # BINARY: the consumer's KF2 update is small.c's
    nm -A "$2" | grep -q 'small.c.o:.* T gf_kf2_update$' ||
        gf_die "$1: the library is not GF_SMALL's"
}
cmake -S tests/consumer -B "$b/subdir-small" -DGAUSSFILT_SOURCE_DIR="$GF_ROOT" \
    -DGAUSSFILT_SMALL=ON >/dev/null
cmake --build "$b/subdir-small" >/dev/null
small_check "add_subdirectory, GAUSSFILT_SMALL=ON" "$b/subdir-small/gaussfilt/libgaussfilt.a"
out=$("$b/subdir-small/consumer")
grep -qF "$want" <<<"$out" || gf_die "add_subdirectory consumer (GF_SMALL) printed: $out"
echo "add_subdirectory(), GAUSSFILT_SMALL=ON: $(head -1 <<<"$out")"

cmake -S . -B "$b/lib-small" -DGAUSSFILT_BUILD_TESTS=OFF -DGAUSSFILT_BUILD_EXAMPLES=OFF \
    -DCMAKE_BUILD_TYPE=MinSizeRel -DCMAKE_INSTALL_PREFIX="$b/prefix-small" >/dev/null
cmake --build "$b/lib-small" >/dev/null
cmake --install "$b/lib-small" >/dev/null
small_check "MinSizeRel install" "$(find "$b/prefix-small" -name libgaussfilt.a | head -1)"
cmake -S tests/consumer -B "$b/pkg-small" -DCMAKE_PREFIX_PATH="$b/prefix-small" >/dev/null
cmake --build "$b/pkg-small" >/dev/null
out=$("$b/pkg-small/consumer")
grep -qF "$want" <<<"$out" || gf_die "find_package consumer (MinSizeRel) printed: $out"
echo "find_package(gaussfilt), MinSizeRel library (GF_SMALL by default): $(head -1 <<<"$out")"
