#!/usr/bin/env bash
# The installed library is usable on its own, the three ways a program outside the project builds
# against it: install the build into a temporary prefix, then compile the example with only that
# prefix's include/ (no private header can be reached), by hand (-I -L -lporeshell), through CMake's
# find_package(poreshell) -> poreshell::poreshell and through pkg-config's poreshell.pc. The first is run;
# the other two are checked to load the prefix's libporeshell (the same program: running it twice more
# would only add its time, some seconds each under the sanitizers).
set -euo pipefail
build_dir="$1" source_dir="$2" cxx="$3" extra_flags="${4:-}"  # the sanitizer flags of the build, if any
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build_dir" --prefix "$prefix" >/dev/null
test ! -e "$prefix/include/core" -a ! -e "$prefix/include/pipeline"  # only the public headers
headers=$(find "$prefix/include" -name '*.hpp' | wc -l)
libdir=$(dirname "$(find "$prefix" -name 'libporeshell.so' | head -1)")
echo "installed: $headers public headers, $(ls "$libdir")"
example="$(cd "$source_dir" && pwd)/examples/perforate_sphere.cpp"
flags="-Wall -Wextra -Werror $extra_flags"
loads_installed_library() {  # the library ldd finds for it is the prefix's (by its real path)
  local found
  found="$(ldd "$1" | awk '/libporeshell/ {print $3}')"
  [ -n "$found" ] && [ "$(realpath "$found")" = "$(realpath "$libdir/libporeshell.so")" ] ||
    { echo "$1 loads libporeshell from '$found', not $libdir"; exit 1; }
}

# By hand.
mkdir "$prefix/by-hand"
"$cxx" -std=c++20 $flags -I"$prefix/include" "$example" -L"$libdir" -lporeshell -Wl,-rpath,"$libdir" \
  -o "$prefix/by-hand/perforate_sphere"
(cd "$prefix/by-hand" && ./perforate_sphere >/dev/null && test -s sphere.stl)

# CMake: a project that knows only the prefix (CMAKE_PREFIX_PATH) and the package's name.
mkdir -p "$prefix/consumer"
cat >"$prefix/consumer/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.24)
project(consumer LANGUAGES CXX)
find_package(poreshell 0.1 REQUIRED)
add_executable(perforate_sphere "$example")
target_link_libraries(perforate_sphere PRIVATE poreshell::poreshell)
CMAKE
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S "$prefix/consumer" -B "$prefix/consumer/build" "${generator[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/consumer/build" >/dev/null
loads_installed_library "$prefix/consumer/build/perforate_sphere"
echo "find_package(poreshell): $(grep -o 'poreshell_DIR:PATH=.*' "$prefix/consumer/build/CMakeCache.txt")"

# pkg-config, with only the prefix's .pc on its path.
export PKG_CONFIG_PATH="$libdir/pkgconfig" PKG_CONFIG_LIBDIR="$libdir/pkgconfig"
mkdir "$prefix/pkg-config"
# shellcheck disable=SC2046  # pkg-config's output is a list of flags
"$cxx" -std=c++20 $flags $(pkg-config --cflags poreshell) "$example" $(pkg-config --libs poreshell) \
  -Wl,-rpath,"$(pkg-config --variable=libdir poreshell)" -o "$prefix/pkg-config/perforate_sphere"
loads_installed_library "$prefix/pkg-config/perforate_sphere"
echo "pkg-config poreshell $(pkg-config --modversion poreshell): $(pkg-config --cflags --libs poreshell)"
