#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Ensures the Debian packages a make target needs are installed.
# usage: mk/deps.sh PACKAGE...     these packages
#        mk/deps.sh --list SET     print a set read from debian/control:
#            build  what `make` needs: Build-Depends-Arch without <!nocheck>
#            check  what `make check` needs (it also builds the .deb): every
#                   build dependency, the <!nocheck> test tools included
#        build-essential, implied by Debian policy, is part of both sets.
# As root it installs what is missing with apt-get; otherwise it prints the
# exact command to run and fails.
set -eu
CONTROL="$(dirname "$0")/../debian/control"

# Whether an architecture restriction ("amd64 i386" or "!arm64") admits
# this machine's Debian architecture.
arch_admits() {
    this=$(dpkg --print-architecture 2>/dev/null || echo unknown)
    negated=0
    for arch in $1; do
        case "$arch" in
        "!$this") return 1 ;;
        "!"*) negated=1 ;;
        "$this") return 0 ;;
        esac
    done
    [ "$negated" = 1 ]
}

# The dependencies of the named fields, one package per line: the first of
# alternatives, without versions or profiles; entries restricted to
# <!nocheck> only with keep_check=1, entries restricted to other
# architectures ([amd64]) not at all.
control_packages() {
    keep_check=$1
    shift
    awk -v fields="$*" '
        BEGIN { n = split(fields, f, " "); for (i = 1; i <= n; i++) want[f[i] ":"] = 1 }
        /^#/ { next }
        /^[^ \t]/ { on = ($1 in want); if (on) { sub(/^[^:]*:/, ""); print }; next }
        on { print }
    ' "$CONTROL" | tr ',' '\n' | while IFS= read -r entry; do
        case "$entry" in *"<!nocheck>"*) [ "$keep_check" = 1 ] || continue ;; esac
        case "$entry" in
        *"["*"]"*) arch_admits "$(printf '%s\n' "$entry" | sed 's/.*\[\(.*\)\].*/\1/')" || continue ;;
        esac
        pkg=$(printf '%s\n' "$entry" | sed -e 's/|.*//' -e 's/[([<].*//' -e 's/:[a-z]*//' \
            -e 's/[[:space:]]//g')
        [ -n "$pkg" ] || continue
        # debhelper-compat is a virtual package that debhelper provides
        [ "$pkg" = debhelper-compat ] && pkg=debhelper
        echo "$pkg"
    done
}

if [ "${1:-}" = "--list" ]; then
    case "${2:-}" in
    build) packages=$(control_packages 0 Build-Depends-Arch) ;;
    check) packages=$(control_packages 1 Build-Depends Build-Depends-Arch Build-Depends-Indep) ;;
    *)
        echo "deps: usage: mk/deps.sh --list build|check" >&2
        exit 2
        ;;
    esac
    # shellcheck disable=SC2086
    echo build-essential $packages
    exit 0
fi

missing=""
for pkg in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $pkg"
    fi
done
[ -z "$missing" ] && exit 0

# Another apt or dpkg at work (unattended-upgrades, a second make) holds
# their locks: wait for it, up to APT_LOCK_WAIT seconds (default 900),
# rather than fail. apt-get waits for the dpkg lock itself
# (DPkg::Lock::Timeout); `update` does not wait for the package lists'
# lock, so it is tried again, once a second, while that lock is held.
lock_wait=${APT_LOCK_WAIT:-900}
update_lists() {
    waited=0
    while ! out=$(apt-get -o DPkg::Lock::Timeout="$lock_wait" update -qq 2>&1); do
        case "$out" in
        *"Could not get lock"*) ;;
        *)
            printf '%s\n' "$out" >&2
            return 1
            ;;
        esac
        if [ "$waited" -ge "$lock_wait" ]; then
            printf '%s\n' "$out" >&2
            return 1
        fi
        if [ "$waited" = 0 ]; then
            echo "deps: another apt holds the package lists; waiting for it (at most ${lock_wait} s)" >&2
        fi
        sleep 1
        waited=$((waited + 1))
    done
    [ -z "$out" ] || printf '%s\n' "$out" >&2
}

if [ "$(id -u)" = "0" ]; then
    echo "deps: installing$missing" >&2
    export DEBIAN_FRONTEND=noninteractive
    update_lists
    # shellcheck disable=SC2086
    apt-get -o DPkg::Lock::Timeout="$lock_wait" install -y -qq --no-install-recommends \
        $missing >&2
    exit 0
fi
echo "deps: missing Debian packages:$missing" >&2
echo "deps: run:  sudo apt-get update && sudo apt-get install -y$missing" >&2
exit 1
