#!/usr/bin/env bash
# The installed library is usable on its own: install the build into a temporary prefix, compile the
# example with only that prefix's include/ (no private header can be reached) and run it.
set -euo pipefail
build_dir="$1" source_dir="$2" cxx="$3" extra_flags="${4:-}"  # the sanitizer flags of the build, if any
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build_dir" --prefix "$prefix" >/dev/null
test ! -e "$prefix/include/core" -a ! -e "$prefix/include/pipeline"  # only the public headers
headers=$(find "$prefix/include" -name '*.hpp' | wc -l)
echo "installed: $headers public headers, $(ls "$prefix/lib")"
"$cxx" -std=c++20 -Wall -Wextra -Werror $extra_flags -I"$prefix/include" "$source_dir/examples/perforate_sphere.cpp" \
  -L"$prefix/lib" -lporeshell -Wl,-rpath,"$prefix/lib" -o "$prefix/perforate_sphere"
cd "$prefix" && ./perforate_sphere && test -s sphere.stl
