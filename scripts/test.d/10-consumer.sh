# SPDX-License-Identifier: MIT
# Another project takes gaussfilt the ways README.md's "Vendoring" and
# docs/firmware.md's show, each with their own text (taken out between its
# marker comments, so the docs cannot drift from what is tested):
#   - the README's examples (KF2, EKF3 with a callback, a 4-state gf_kf) as
#     C99 and as C++17,
#     -Wall -Wextra -Wpedantic -Werror, printing what the README says;
#   - the CMake snippet with add_subdirectory() on a copy holding only
#     CMakeLists.txt, include/ and src/ (no cmake/, no tests/): it builds,
#     and the parent's cmake --install installs nothing of gaussfilt;
#   - the host compiler line on copied sources;
#   - the file table: each row's sources define everything they call but
#     the C library and the libm functions the row names;
#   - add_subdirectory() of the whole tree, and cmake --install +
#     find_package(gaussfilt);
#   - a program built for the other precision than its library does not
#     link (and the matching one does).
# The Cortex-M4F compiler line and the cross snippet are in 30-cross.sh.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt cmake make gcc g++ libc6-dev binutils
b=$GF_BUILD/consumer
rm -rf "$b"
mkdir -p "$b/examples"

# The examples and what the README says they print.
for ex in kf2 ekf3 kf4; do
    gf_readme_block "example-$ex" >"$b/examples/$ex.c"
    cp "$b/examples/$ex.c" "$b/examples/$ex.cpp"
    sed -n "s/.*<!-- example-$ex-prints -->\`\(.*\)\`<!-- \/example-$ex-prints -->.*/\1/p" \
        README.md >"$b/examples/$ex.want"
    [ -s "$b/examples/$ex.want" ] ||
        gf_die "README.md: no <!-- example-$ex-prints --> for the $ex example"
done

# expect_prints WHAT PROGRAM EXAMPLE: PROGRAM prints EXAMPLE's README line.
expect_prints() {
    local what=$1 prog=$2 want out
    want=$(cat "$b/examples/$3.want")
    out=$("$prog") || gf_die "$what: $prog failed: $out"
    [ "$out" = "$want" ] || gf_die "$what: $prog printed '$out', README.md says '$want'"
    echo "$what: $(basename "$prog") prints $out"
}

# vendor_copy DIR: what the README says to copy.
vendor_copy() {
    mkdir -p "$1/include"
    cp CMakeLists.txt "$1/"
    cp -r include/gaussfilt "$1/include/"
    cp -r src "$1/"
}

gf_log "consumer: docs/firmware.md's CMake snippet, add_subdirectory() of a copy"
v=$b/vendored
mkdir -p "$v/src"
vendor_copy "$v/src/gaussfilt"
gf_readme_block vendor-cmake >"$v/src/CMakeLists.txt"
cp "$b/examples/kf2.c" "$v/src/main.c"
cmake -S "$v/src" -B "$v/build" -DCMAKE_BUILD_TYPE=Release >"$v/configure.log" 2>&1 ||
    gf_die "the documented CMake snippet does not configure (see $v/configure.log)"
cmake --build "$v/build" >"$v/build.log" 2>&1 ||
    gf_die "the documented CMake snippet does not build (see $v/build.log)"
expect_prints "CMake snippet" "$v/build/app" kf2
grep -q 'GAUSSFILT_BUILD_TESTS:BOOL=OFF' "$v/build/CMakeCache.txt" ||
    gf_die "add_subdirectory: GAUSSFILT_BUILD_TESTS is not OFF by default"
cmake --install "$v/build" --prefix "$v/prefix" >/dev/null
[ -z "$(find "$v/prefix" -name 'libgaussfilt*' -o -name gaussfilt -type d 2>/dev/null)" ] ||
    gf_die "add_subdirectory: the parent's cmake --install installed gaussfilt"
echo "add_subdirectory(): no tests built, nothing of gaussfilt installed by the parent"

gf_log "consumer: docs/firmware.md's host compiler line on copied sources"
c=$b/copied
mkdir -p "$c"
vendor_copy "$c/gaussfilt"
line=$(gf_readme_block vendor-cc | sed -n '1,/^$/p' | sed '/^$/d')
[ "${line%% *}" = cc ] || gf_die "docs/firmware.md's first compiler line is not cc's: $line"
echo "$line"
for ex in kf2 ekf3 kf4; do
    cp "$b/examples/$ex.c" "$c/main.c"
    (cd "$c" && bash -euc "$line") || gf_die "docs/firmware.md's compiler line failed on the $ex example"
    mv "$c/app" "$c/app-$ex"
    expect_prints "copied sources" "$c/app-$ex" "$ex"
done

gf_log "consumer: README's file table, each row's sources against nm"
o=$b/objects
mkdir -p "$o"
for src in src/*.c; do
    gcc -std=c99 -O2 -Iinclude -c "$src" -o "$o/$(basename "$src" .c).o"
done
rows=$(gf_readme_block vendor-files | grep -E '^\| [^-]' | tail -n +2)
[ -n "$rows" ] || gf_die "README.md: the file table has no rows"
while IFS='|' read -r _ what files libm _; do
    objs=()
    for f in $(grep -oE '[a-z0-9_]+\.c' <<<"$files"); do
        [ -f "$o/${f%.c}.o" ] || gf_die "README file table ($what): no src/$f"
        objs+=("$o/${f%.c}.o")
    done
    allowed=$( (grep -oE '`[a-z0-9]+`' <<<"$libm" || true) | tr -d '`' | tr '\n' '|')
    missing=$(comm -23 <(nm -u "${objs[@]}" | awk '$1 == "U" {print $2}' | sort -u) \
        <(nm --defined-only "${objs[@]}" | awk 'NF == 3 {print $3}' | sort -u) |
        grep -vxE "${allowed}memset|memcpy" || true)
    [ -z "$missing" ] || gf_die "README file table, row '$(xargs <<<"$what")': \
$(xargs <<<"$files") also need $(tr '\n' ' ' <<<"$missing")"
    echo "ok: $(tr -d '`' <<<"$what" | xargs): $(tr -d '`' <<<"$files" | xargs) (libm: $(tr -d '`' <<<"$libm" | xargs))"
done <<<"$rows"

gf_log "consumer: add_subdirectory() of the tree, the examples as C and C++"
cmake -S tests/consumer -B "$b/subdir" -DGAUSSFILT_SOURCE_DIR="$GF_ROOT" \
    -DGF_EXAMPLES_DIR="$b/examples" >/dev/null
cmake --build "$b/subdir" --parallel 2 >/dev/null ||
    cmake --build "$b/subdir" || gf_die "the examples do not build (as C or C++17)"
for ex in kf2 ekf3 kf4; do
    for lang in c cxx; do
        expect_prints "add_subdirectory(), $lang" "$b/subdir/${ex}_$lang" "$ex"
    done
done

gf_log "consumer: cmake --install, find_package(gaussfilt), double and float"
for prec in double float; do
    single=OFF
    [ "$prec" = float ] && single=ON
    cmake -S . -B "$b/lib-$prec" -DGAUSSFILT_BUILD_TESTS=OFF -DGAUSSFILT_BUILD_EXAMPLES=OFF \
        -DGAUSSFILT_SINGLE_PRECISION=$single -DCMAKE_INSTALL_PREFIX="$b/prefix-$prec" >/dev/null
    cmake --build "$b/lib-$prec" --parallel 2 >/dev/null
    cmake --install "$b/lib-$prec" >/dev/null
    cmake -S tests/consumer -B "$b/pkg-$prec" -DCMAKE_PREFIX_PATH="$b/prefix-$prec" \
        -DGF_EXAMPLES_DIR="$b/examples" >/dev/null
    cmake --build "$b/pkg-$prec" --parallel 2 >/dev/null ||
        gf_die "find_package consumer ($prec) does not build"
    for ex in kf2 ekf3 kf4; do
        for lang in c cxx; do
            expect_prints "find_package(gaussfilt), $prec, $lang" "$b/pkg-$prec/${ex}_$lang" "$ex"
        done
    done
done

gf_log "consumer: a program built for the other precision does not link"
for lib in double float; do
    a=$(find "$b/prefix-$lib" -name libgaussfilt.a | head -1)
    for app in double float; do
        def=() suffix=_f64
        [ "$app" = float ] && def=(-DGF_SINGLE_PRECISION) suffix=_f32
        log=$b/mismatch-$lib-$app.log
        if gcc -std=c99 "${def[@]}" -I"$b/prefix-$lib/include" "$b/examples/kf2.c" \
            "$a" -lm -o "$b/mismatch-$lib-$app" >"$log" 2>&1; then
            [ "$lib" = "$app" ] ||
                gf_die "a $app program linked against the $lib library"
            expect_prints "$app program, $lib library" "$b/mismatch-$lib-$app" kf2
        else
            [ "$lib" != "$app" ] ||
                gf_die "a $app program does not link against the $lib library: $(cat "$log")"
            grep -q "undefined reference to .gf_kf2_[a-z_]*$suffix'" "$log" ||
                gf_die "$app program, $lib library: the link failed, but not on a $suffix name: $(cat "$log")"
            echo "$app program, $lib library: does not link ($(grep -o "undefined reference to .gf_kf2_init$suffix'" "$log" | head -1))"
        fi
    done
done
