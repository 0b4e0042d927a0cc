#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fetches and builds the public WSG drivers that tools/drivers/run_driver.py
# runs against wsgsim. Nothing of theirs enters this source tree: each is
# extracted at run time into DIR (outside the tree), from a git URL, a git
# checkout, a bare git directory or a plain source folder.
#
# usage: tools/drivers/build.sh DIR ROS_SOURCE UMI_SOURCE DRAKE_SCHUNK_SOURCE
#
#   ROS_SOURCE            wsg50-ros-pkg (nalt's ROS 1 driver), built with
#                         Debian's catkin and clang into DIR/ros
#   UMI_SOURCE            universal_manipulation_interface: its
#                         wsg_binary_driver.py and cmd_measure.lua, into DIR/umi
#   DRAKE_SCHUNK_SOURCE   drake-schunk-driver: its demo.cc and the message
#                         code it needs, built with clang++ into DIR/drake
#
# DIR/sources.txt names each source and its commit (when it is a git one).
set -eu

if [ $# -ne 4 ]; then
    echo "usage: $0 DIR ROS_SOURCE UMI_SOURCE DRAKE_SCHUNK_SOURCE" >&2
    exit 2
fi
DIR=$1
ROS_SOURCE=$2
UMI_SOURCE=$3
DRAKE_SOURCE=$4
# catkin and the ROS tools are Debian's: they need Debian's Python, not one
# a version manager put first on PATH
PATH=/usr/sbin:/usr/bin:/sbin:/bin
export PATH

# A git directory to read from: a bare one, a checkout's .git, or a shallow
# clone (into DIR/clones) of a URL. Prints nothing for a plain folder.
git_dir_of() {
    source=$1
    name=$2
    if [ -f "$source/HEAD" ] && [ -d "$source/objects" ]; then
        echo "$source"
    elif [ -d "$source/.git" ] || [ -f "$source/.git" ]; then
        git -C "$source" rev-parse --absolute-git-dir
    elif [ -d "$source" ]; then
        :
    else
        clone="$DIR/clones/$name"
        if [ ! -d "$clone" ]; then
            mkdir -p "$DIR/clones"
            git clone --quiet --bare --depth 1 "$source" "$clone"
        fi
        echo "$clone"
    fi
}

# Extracts the named paths of a source into DIR/src/NAME.
extract() {
    source=$1
    name=$2
    shift 2
    target="$DIR/src/$name"
    rm -rf "$target"
    mkdir -p "$target"
    gitdir=$(git_dir_of "$source" "$name")
    if [ -n "$gitdir" ]; then
        # file by file: a partial mirror may lack other blobs of the tree
        git --git-dir="$gitdir" ls-tree -r --name-only HEAD -- "$@" | while IFS= read -r file; do
            mkdir -p "$target/$(dirname "$file")"
            git --git-dir="$gitdir" show "HEAD:$file" >"$target/$file"
        done
        commit=$(git --git-dir="$gitdir" rev-parse HEAD)
    else
        for path in "$@"; do
            mkdir -p "$target/$(dirname "$path")"
            cp -R "$source/$path" "$target/$path"
        done
        commit=unknown
    fi
    echo "$name $source $commit" >>"$DIR/sources.txt.tmp"
}

build_ros() {
    workspace="$DIR/ros"
    rm -rf "$workspace"
    mkdir -p "$workspace/src"
    cp -R "$DIR/src/wsg50-ros-pkg/wsg_50_common" "$DIR/src/wsg50-ros-pkg/wsg_50_driver" \
        "$workspace/src/"
    (cd "$workspace" && CC=clang CXX=clang++ catkin_make -j2 \
        -DPYTHON_EXECUTABLE=/usr/bin/python3 >build.log 2>&1) || {
        tail -n 30 "$workspace/build.log" >&2
        echo "drivers: building wsg50-ros-pkg failed; the log: $workspace/build.log" >&2
        exit 1
    }
    test -x "$workspace/devel/lib/wsg_50_driver/wsg_50_ip"
}

# The demo (home both ways, preposition, grasp) needs none of Drake's
# libraries: only the driver's own message code.
build_drake_demo() {
    src="$DIR/src/drake-schunk-driver/src"
    mkdir -p "$DIR/drake"
    # its wsg.h narrows an enum in a braced list, which clang refuses
    # unless told otherwise
    clang++ -std=c++14 -O1 -Wno-c++11-narrowing -o "$DIR/drake/demo" "$src/demo.cc" \
        "$src/wsg_command_message.cc" "$src/wsg_command_sender.cc" \
        "$src/wsg_return_message.cc" "$src/wsg_return_receiver.cc"
}

mkdir -p "$DIR"
rm -f "$DIR/sources.txt.tmp"
extract "$ROS_SOURCE" wsg50-ros-pkg wsg_50_common wsg_50_driver
extract "$UMI_SOURCE" umi umi/real_world/wsg_binary_driver.py umi/real_world/cmd_measure.lua
extract "$DRAKE_SOURCE" drake-schunk-driver src
mv "$DIR/sources.txt.tmp" "$DIR/sources.txt"
build_ros
build_drake_demo
echo "drivers: built in $DIR"
cat "$DIR/sources.txt"
