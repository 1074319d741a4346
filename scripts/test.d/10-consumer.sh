# Another project takes gaussfilt by add_subdirectory() and, after
# cmake --install, by find_package(gaussfilt); both run the README example.
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
