#!/bin/sh
# The installed package is relocatable: copy the prefix elsewhere, hide the original, then build
# and run the CMake consumer (find_package) and the C example (pkg-config) against the copy.
#   package_moved.sh PREFIX WORKDIR CONSUMER_SRC CMAKE CXX CC PKG_CONFIG(or none) EXAMPLE_C MODEL
set -eu
prefix=$1 work=$2 consumer_src=$3 cmake=$4 cxx=$5 cc=$6 pkg_config=$7 example_c=$8 model=$9
rm -rf "$work"
mkdir -p "$work"
cp -R "$prefix" "$work/prefix"
mv "$prefix" "$prefix.away"
trap 'mv "$prefix.away" "$prefix"' EXIT
"$cmake" -S "$consumer_src" -B "$work/consumer" "-DCMAKE_PREFIX_PATH=$work/prefix" \
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=$cxx"
"$cmake" --build "$work/consumer"
"$work/consumer/consumer_app" "$model"
if [ "$pkg_config" != none ]; then
    libdir=$(ls -d "$work"/prefix/lib*/pkgconfig | head -n 1)
    flags=$(PKG_CONFIG_PATH="$libdir" "$pkg_config" --cflags --libs gbsurf)
    case "$flags" in *"$prefix"*) echo "pkg-config names the original prefix: $flags" >&2; exit 1 ;; esac
    # shellcheck disable=SC2086
    "$cc" -std=c11 -pedantic -Wall -Werror "$example_c" -o "$work/pc_example" $flags
    "$work/pc_example"
fi
echo "package_moved: the copied prefix works"
