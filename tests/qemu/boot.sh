#!/bin/bash
# SPDX-License-Identifier: BSD-3-Clause
# Boots a wsgsim board image in QEMU's mps2-an385 on free local ports.
#
# usage: boot.sh [--test] serial|lwip IMAGE.elf
#   without --test  runs until QEMU exits (Ctrl-C) and prints how to connect
#   with --test     waits for the board, runs tests/qemu/conversation.py
#                   and binary_conversation.py against it (serial: over
#                   UART0; lwip: over TCP and UDP 1000, binary UDP 1500
#                   through hostfwd), and web_status.py against the lwIP
#                   image's status page, and always stops QEMU afterwards.
# Ports: GCL_PORT (serial socket or forwarded TCP), GCL_UDP_PORT,
# BIN_UDP_PORT and HTTP_PORT (the lwIP image's status page) default to free
# ones. The board sends binary UDP replies to the sender's address at port
# 1501, which QEMU delivers to 127.0.0.1:1501: the binary UDP test needs that
# port. So --test runs in a network namespace of its own (unshare -rn,
# util-linux), where that port and the forwarded ones are this run's alone
# whatever else runs on the machine (other suites, a wsgsim someone
# started); where no namespace can be made, on this host's loopback.
# QEMU_TIMEOUT bounds the whole run in --test mode (seconds).
# Both bounds only stop a hung run: QEMU on a busy machine boots slowly.
set -euo pipefail

if [ "${1:-}" = "--test" ] && [ -z "${WSGSIM_QEMU_NETNS:-}" ] && unshare -rn true 2>/dev/null; then
    exec env WSGSIM_QEMU_NETNS=1 unshare -rn "$0" "$@"
fi

here=$(cd "$(dirname "$0")" && pwd)
test_mode=0
if [ "${1:-}" = "--test" ]; then
    test_mode=1
    shift
fi
kind=${1:?usage: boot.sh [--test] serial|lwip IMAGE.elf}
image=${2:?usage: boot.sh [--test] serial|lwip IMAGE.elf}
case $kind in serial | lwip) ;; *)
    echo "boot.sh: unknown image kind '$kind'" >&2
    exit 2
    ;;
esac

fail() {
    echo "FAIL  qemu-$kind: $*" >&2
    exit 1
}

command -v qemu-system-arm >/dev/null || fail "qemu-system-arm is not installed (make deps: qemu-system-arm)"
command -v python3 >/dev/null || fail "python3 is not installed"
[ -f "$image" ] || fail "no image $image (make firmware)"

# Ports nobody listens on now, one per socket type given (SOCK_STREAM or
# SOCK_DGRAM). All are held open until each is picked: a socket closed
# before the next is bound can get its port again, and QEMU refuses two
# forwarding rules on one UDP port.
free_ports() {
    python3 -c 'import socket,sys
held = []
for kind in sys.argv[1:]:
    s = socket.socket(socket.AF_INET, getattr(socket, kind))
    s.bind(("127.0.0.1", 0)); held.append(s)
print(" ".join(str(s.getsockname()[1]) for s in held))' "$@"
}

# A new network namespace's loopback is down until brought up.
loopback_up() {
    python3 -c 'import fcntl, socket, struct
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
request = struct.pack("16sH14x", b"lo", 0)
flags = struct.unpack("16sH14x", fcntl.ioctl(s, 0x8913, request))[1]  # SIOCGIFFLAGS
fcntl.ioctl(s, 0x8914, struct.pack("16sH14x", b"lo", flags | 1))  # SIOCSIFFLAGS, IFF_UP'
}
if [ -n "${WSGSIM_QEMU_NETNS:-}" ]; then
    loopback_up
    echo "qemu-$kind: in a network namespace of its own"
fi

read -r picked_tcp picked_udp picked_http picked_bin_udp < <(free_ports SOCK_STREAM SOCK_DGRAM SOCK_STREAM SOCK_DGRAM)
tcp_port=${GCL_PORT:-$picked_tcp}
udp_port=${GCL_UDP_PORT:-$picked_udp}
http_port=${HTTP_PORT:-$picked_http}
bin_udp_port=${BIN_UDP_PORT:-$picked_bin_udp}
board_ip=192.168.1.20
workdir=$(mktemp -d "${TMPDIR:-/tmp}/wsgsim-qemu.XXXXXX")

# QEMU user networking: the guest sees only forwarded ports. restrict=on
# isolates it completely, but libslirp (4.7, udp_input) then drops every UDP
# datagram the guest sends, replies to hostfwd included; so UDP is served
# with restrict=off. The board has no gateway and opens no connections.
set_qemu_args() { # RESTRICT -> qemu_args (UART1 is added by the caller)
    qemu_args=(-M mps2-an385 -nodefaults -display none -monitor none -kernel "$image")
    if [ "$kind" = serial ]; then
        qemu_args+=(-serial "tcp:127.0.0.1:$tcp_port,server=on,wait=off,nodelay=on" -nic none)
    else
        # UART0 carries GCL too, but in this setup nothing listens to it.
        local fwd="hostfwd=tcp:127.0.0.1:$tcp_port-$board_ip:1000,hostfwd=udp:127.0.0.1:$udp_port-$board_ip:1000"
        fwd+=",hostfwd=tcp:127.0.0.1:$http_port-$board_ip:80"
        fwd+=",hostfwd=udp:127.0.0.1:$bin_udp_port-$board_ip:1500"
        qemu_args+=(-serial null -nic "user,model=lan9118,net=192.168.1.0/24,restrict=$1,$fwd")
    fi
}

qemu_pid=""
stop_qemu() {
    if [ -n "$qemu_pid" ] && kill -0 "$qemu_pid" 2>/dev/null; then
        kill "$qemu_pid" 2>/dev/null || true
        wait "$qemu_pid" 2>/dev/null || true
    fi
    qemu_pid=""
}
cleanup() {
    stop_qemu
    rm -rf "$workdir"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if [ $test_mode = 0 ]; then
    restrict=${QEMU_RESTRICT:-on}
    echo "Booting $image on QEMU mps2-an385 (Ctrl-C to stop)."
    if [ "$kind" = serial ]; then
        echo "GCL on UART0:  nc 127.0.0.1 $tcp_port      (or: python3 tests/qemu/conversation.py 127.0.0.1 $tcp_port)"
    else
        echo "GCL over lwIP at $board_ip:1000 (user network, restrict=$restrict), forwarded to"
        echo "  TCP:  nc 127.0.0.1 $tcp_port"
        echo "  UDP:  nc -u 127.0.0.1 $udp_port"
        echo "  status page: http://127.0.0.1:$http_port/"
        echo "  or:   python3 tests/qemu/conversation.py 127.0.0.1 $tcp_port --udp $udp_port"
        echo "Binary protocol: on the TCP port (first byte 0xAA), and UDP 1500 forwarded to"
        echo "  python3 tests/qemu/binary_conversation.py 127.0.0.1 $bin_udp_port --udp (replies at 1501)"
        [ "$restrict" = on ] && echo "  note: with restrict=on QEMU drops the board's UDP replies; use QEMU_RESTRICT=off for UDP"
    fi
    echo "Device log (UART1) follows."
    set_qemu_args "$restrict"
    qemu-system-arm "${qemu_args[@]}" -serial stdio &
    qemu_pid=$!
    wait "$qemu_pid"
    exit $?
fi

# Boots the image, waits for its "ready" line on UART1, runs the GCL
# conversation with the given arguments, then the binary one with
# BINARY-ARGS ("-": none), and stops QEMU whatever happened.
run_test() { # LABEL RESTRICT BINARY-ARGS CONVERSATION-ARGS...
    local label=$1 restrict=$2 binary_args=$3
    shift 3
    local log="$workdir/$label-uart1.log" err="$workdir/$label-qemu.err"
    : >"$log"
    set_qemu_args "$restrict"
    timeout "${QEMU_TIMEOUT:-600}" qemu-system-arm "${qemu_args[@]}" -serial "file:$log" 2>"$err" &
    qemu_pid=$!
    for _ in $(seq 1 600); do
        grep -q "ready" "$log" 2>/dev/null && break
        kill -0 "$qemu_pid" 2>/dev/null || fail "QEMU exited early: $(cat "$err")"
        sleep 0.1
    done
    grep -q "ready" "$log" || fail "the board did not report ready within 60 s; UART1: $(cat "$log")"
    echo "$label: $(grep ready "$log" | head -n 1)"
    local status=0
    python3 "$here/conversation.py" 127.0.0.1 "$tcp_port" "$@" || status=$?
    if [ "$binary_args" != - ] && [ $status = 0 ]; then
        # shellcheck disable=SC2086 # the arguments are words on purpose
        python3 "$here/binary_conversation.py" 127.0.0.1 $binary_args || status=$?
    fi
    if [ "$label" = qemu-lwip-tcp ] && [ $status = 0 ]; then
        # the status page on port 80 (web_status.py)
        python3 "$here/web_status.py" 127.0.0.1 "$tcp_port" "$http_port" || status=$?
    fi
    stop_qemu
    if [ $status != 0 ]; then
        echo "$label: device log (UART1):" >&2
        sed 's/^/  | /' "$log" >&2
        [ -s "$err" ] && sed 's/^/  qemu: /' "$err" >&2
        fail "the conversation failed"
    fi
    grep "stack:" "$log" | tail -n 1 | sed "s/^/$label: /" || true
    local what="GCL and binary"
    [ "$binary_args" = - ] && what=GCL
    echo "PASS  $label: $what conversation"
}

if [ "$kind" = serial ]; then
    # GCL's BYE ends the UART session; the next one starts binary (0xAA)
    run_test qemu-serial on "$tcp_port --serial" --name uart0
else
    run_test qemu-lwip-tcp on "$tcp_port" --name tcp
    run_test qemu-lwip-udp off "$bin_udp_port --udp" --no-tcp --udp "$udp_port"
fi
