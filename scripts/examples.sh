#!/bin/sh
# Build examples/*.c against an installed radkit the way a user would, run
# them, and check their figures against the installed program's own:
#
#   sh scripts/examples.sh PREFIX OUT      (make examples stages PREFIX first)
#
# PREFIX is where radkit is installed (bin, lib, include, share under it; it
# may be a staged DESTDIR copy: pkg-config's --define-prefix takes the prefix
# from where radkit.pc lies).  OUT receives the programs and their output.
# Checks, each failing the script:
#   - every installed header compiles on its own with pkg-config's Cflags;
#   - libradkit.so exports rad_* names only, and every rad_* function the
#     headers declare;
#   - each example links shared (pkg-config --libs), static (libradkit.a with
#     pkg-config --static's private libraries; no libradkit.so needed), and
#     with clang when it is installed (the static library's fat LTO objects);
#   - form_factor's F12 and F21 equal `radkit ff`'s for the same pair and
#     rules, galerkin1d's errors equal `radkit galerkin1d`'s, solve_scene's
#     per-face table (every digit) and error estimate equal `radkit solve
#     --method hier`'s on the Cornell box.
set -eu
prefix=${1:?usage: sh scripts/examples.sh PREFIX OUT}
out=${2:?usage: sh scripts/examples.sh PREFIX OUT}
cd "$(dirname "$0")/.."
mkdir -p "$out"
CC=${CC:-cc}
radkit=$prefix/bin/radkit
libdir=$prefix/lib
export PKG_CONFIG_PATH="$libdir/pkgconfig"
pc() { pkg-config --define-prefix "$@" radkit; }
fail() { echo "examples: $*" >&2; exit 1; }
cflags=$(pc --cflags)
libs=$(pc --libs)
static_libs=$(pc --static --libs | sed 's/-lradkit\b/-l:libradkit.a/')
echo "examples: pkg-config radkit $(pc --modversion): $cflags $libs"

# Headers: each one alone (they include each other by bare name).
for h in "$prefix"/include/radkit/*.h; do
    printf '#include <%s>\nint main(void) { return 0; }\n' "${h##*/}" |
        $CC -std=c11 -Wall -Wextra -Werror -fsyntax-only $cflags -x c - ||
        fail "${h##*/} does not compile on its own"
done
echo "examples: $(ls "$prefix"/include/radkit/*.h | wc -l) headers compile on their own"

# Exports: the rad_* API and nothing else.
nm -D --defined-only "$libdir/libradkit.so" | awk '{ print $3 }' | sort -u > "$out/exported.txt"
hidden_leak=$(grep -v '^rad_' "$out/exported.txt" || true)
[ -z "$hidden_leak" ] || fail "libradkit.so exports non-API names: $(echo $hidden_leak | head -c 300)"
# Declared functions: GCC's -aux-info lists every prototype a translation
# unit declares; the extern ones from the installed headers are the API
# (static inline helpers such as rad_vec3_add are not library symbols).
for h in "$prefix"/include/radkit/*.h; do printf '#include <%s>\n' "${h##*/}"; done > "$out/all_headers.c"
gcc -std=c11 -fsyntax-only $cflags -aux-info "$out/aux-info.txt" "$out/all_headers.c"
# (the name is the identifier before the prototype's first parenthesis: a
# parameter such as const rad_vec3 (*)[3] must not count as a declaration)
grep "^/\* $prefix/include/radkit/.* \*/ extern " "$out/aux-info.txt" |
    sed -n 's/^.*\*\/ extern [^(]*\<\(rad_[a-z0-9_]*\) (.*$/\1/p' | sort -u > "$out/declared.txt"
[ -s "$out/declared.txt" ] || fail "no function declarations found in the installed headers"
missing=$(comm -23 "$out/declared.txt" "$out/exported.txt")
[ -z "$missing" ] || fail "declared but not exported: $(echo $missing)"
extra=$(comm -13 "$out/declared.txt" "$out/exported.txt")
[ -z "$extra" ] || fail "exported but declared in no header: $(echo $extra)"
echo "examples: libradkit.so exports $(wc -l < "$out/exported.txt") names, the rad_* functions the headers declare"

# Build every example three ways (-lm: galerkin1d.c calls log itself).
for src in examples/*.c; do
    name=$(basename "$src" .c)
    $CC -std=c11 -O2 -Wall -Wextra -Werror "$src" -o "$out/$name" $cflags $libs -lm ||
        fail "$name: shared link failed"
    $CC -std=c11 -O2 -Wall -Wextra -Werror "$src" -o "$out/$name-static" $cflags $static_libs -lm ||
        fail "$name: static link failed"
    ! readelf -d "$out/$name-static" | grep -q 'libradkit\.so' || fail "$name-static needs libradkit.so"
    if command -v clang >/dev/null 2>&1; then
        clang -std=c11 -O2 -Wall -Wextra -Werror "$src" -o "$out/$name-clang" $cflags $static_libs -lm ||
            fail "$name: static link with clang failed"
    fi
done

# Run each variant; every one must print the same.
run() {
    name=$1; shift
    for v in '' -static -clang; do
        [ -x "$out/$name$v" ] || continue
        LD_LIBRARY_PATH="$libdir" "$out/$name$v" "$@" > "$out/$name$v.txt" ||
            fail "$name$v failed (exit $?)"
        cmp -s "$out/$name.txt" "$out/$name$v.txt" || fail "$name$v prints other figures than $name"
    done
}
LD_LIBRARY_PATH="$libdir" ldd "$out/form_factor" | grep -q "$libdir/libradkit.so" ||
    fail "form_factor does not load the installed libradkit.so"

# form_factor: both rules' F12 and F21 against radkit ff on the pair it prints.
run form_factor
tri1=$(sed -n 's/^# tri1 = //p' "$out/form_factor.txt")
tri2=$(sed -n 's/^# tri2 = //p' "$out/form_factor.txt")
awk -F '\t' '!/^#/ && $1 != "rule" { print $1, $2, $3 }' "$out/form_factor.txt" |
while read -r rule f12 f21; do
    want=$("$radkit" ff --tri "$tri1" --tri "$tri2" --rule "$rule" | awk -F '\t' '!/^#/ && $1 != "rule" { print $2, $3 }')
    [ "$f12 $f21" = "$want" ] || fail "form_factor $rule: F12 F21 = $f12 $f21, radkit ff says $want"
    echo "examples: form_factor $rule: F12 = $f12, F21 = $f21 (radkit ff agrees)"
done

# galerkin1d: each row's errors against radkit galerkin1d at that n.
run galerkin1d
awk -F '\t' '!/^#/ && $1 != "n" { print $1, $2, $3 }' "$out/galerkin1d.txt" |
while read -r n l2 linf; do
    want=$("$radkit" galerkin1d --n "$n" --problem exp --basis p1 --assembly exact --no-check |
           sed -n 's/^# err_l2 = //p; s/^# err_linf = //p' | tr '\n' ' ')
    [ "$l2 $linf " = "$want" ] || fail "galerkin1d n = $n: errors $l2 $linf, radkit galerkin1d says $want"
    echo "examples: galerkin1d n = $n: err_l2 = $l2, err_linf = $linf (radkit galerkin1d agrees)"
done
# solve_scene: the per-face table and error estimate of radkit solve --method hier.
scene=scenes/cornell/cornell.obj
run solve_scene "$scene"
"$radkit" solve "$scene" --method hier --quiet > "$out/solve_scene.radkit.txt"
sed -n '/^face\t/,$p' "$out/solve_scene.txt" > "$out/solve_scene.rows"
sed -n '/^face\t/,$p' "$out/solve_scene.radkit.txt" > "$out/solve_scene.radkit.rows"
[ -s "$out/solve_scene.rows" ] && cmp -s "$out/solve_scene.rows" "$out/solve_scene.radkit.rows" ||
    fail "solve_scene $scene: the per-face table differs from radkit solve --method hier's"
for key in faces error_estimate; do
    a=$(sed -n "s/^# $key = //p" "$out/solve_scene.txt")
    b=$(sed -n "s/^# $key = //p" "$out/solve_scene.radkit.txt")
    [ -n "$a" ] && [ "$a" = "$b" ] || fail "solve_scene $scene: $key $a, radkit solve says $b"
done
echo "examples: solve_scene $scene: $(($(wc -l < "$out/solve_scene.rows") - 1)) faces, error_estimate $a (radkit solve --method hier agrees)"
echo "examples: all checks passed ($(ls examples/*.c | wc -l) examples, variants: shared static$(command -v clang >/dev/null 2>&1 && echo ' clang'))"
