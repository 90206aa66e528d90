#!/usr/bin/env python3
"""256 slow image readers against `raypool view` at 2048 x 2048 (issue #38, bounded memory):
each connection asks for /image.pfm (48 MiB) and never reads it. Prints, per binary, the
viewer's resident memory before, its peak over 8 s, and the answers' status codes (the
first 12 bytes each reader got; "none" if nothing came within 1 s).

    benches/view_slow_readers.py BINARY [BINARY ...]   (Linux: reads /proc/PID/status)
"""
import socket
import subprocess
import sys
import time

READERS = 256


def resident_kib(pid):
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def ask(host, port, address, path):
    s = socket.create_connection((host, port))
    s.sendall(f"GET {path} HTTP/1.1\r\nHost: {address}\r\n\r\n".encode())
    return s


def measure(binary):
    viewer = subprocess.Popen(
        [binary, "view", "--port", "0", "--scene", "three-spheres", "--width", "2048", "--height", "2048",
         "--spp", "1", "--threads", "2"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    address = viewer.stdout.readline().strip()[len("http://"):].rstrip("/")
    host, port = address.rsplit(":", 1)
    port = int(port)
    while True:  # until the first pass has finished
        s = ask(host, port, address, "/image.png")
        finished = s.recv(12).endswith(b"200")
        s.close()
        if finished:
            break
        time.sleep(0.2)
    before = resident_kib(viewer.pid)
    readers = [ask(host, port, address, "/image.pfm") for _ in range(READERS)]
    peak, start = before, time.time()
    while time.time() - start < 8:
        peak = max(peak, resident_kib(viewer.pid))
        time.sleep(0.05)
    codes = {}
    for s in readers:
        s.settimeout(1)
        try:
            code = s.recv(12)[-3:].decode() or "none"
        except OSError:
            code = "none"
        codes[code] = codes.get(code, 0) + 1
        s.close()
    viewer.terminate()
    viewer.wait()
    print(f"| `{binary}` | {before // 1024} | {peak // 1024} | "
          + ", ".join(f"{n} × {c}" for c, n in sorted(codes.items())) + " |")


if __name__ == "__main__":
    print("| binary | resident before (MiB) | peak with 256 slow readers (MiB) | answers |\n|---|---:|---:|---|")
    for binary in sys.argv[1:]:
        measure(binary)
