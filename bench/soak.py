#!/usr/bin/python3
"""Soak monocled: run it on its embedded default under a steady load of clients and sample its
resident memory, threads and open file descriptors, then report each one's trend.

The load, repeated until the duration is over: a pose stream read for 2 s, a status query,
a 20 000-point floor query (as many as a command line holds comfortably), a one-point one.
Samples go to a CSV (seconds, RSS in MB, threads, descriptors, then RSS's anonymous and
file-backed parts in MB); the report gives first and last values and the least-squares slope
per hour after the first minute (start-up excluded), with its 1-sigma counting the samples'
correlation over 5 minutes. Exit status 1 when a client failed.

  bench/soak.py --duration 3600            # the one-hour soak (issue 62), binaries in build/
  bench/soak.py --duration 120 --csv s.csv # a quick look
"""
import argparse
import os
import random
import signal
import subprocess
import sys
import tempfile
import time


def sample(pid):
    """RSS, its anonymous (heap, stacks) and file-backed (code, mapped files) parts in MB,
    threads, open descriptors."""
    kb = {"VmRSS:": 0, "RssAnon:": 0, "RssFile:": 0, "Threads:": 0}
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            field = line.split(maxsplit=1)[0]
            if field in kb:
                kb[field] = int(line.split()[1])
    return (kb["VmRSS:"] / 1024.0, kb["Threads:"], len(os.listdir(f"/proc/{pid}/fd")),
            kb["RssAnon:"] / 1024.0, kb["RssFile:"] / 1024.0)


def slope_per_hour(times, values, lag):
    """The least-squares slope per hour and its 1-sigma. The samples are not independent (a
    block the allocator keeps stays for minutes), so the 1-sigma is Newey and West's: the
    residuals' correlations up to `lag` samples apart are counted, Bartlett-weighted."""
    n = len(times)
    if n < 3:
        return 0.0, 0.0
    mt, mv = sum(times) / n, sum(values) / n
    x = [t - mt for t in times]
    sxx = sum(a * a for a in x)
    if sxx <= 0:
        return 0.0, 0.0
    b = sum(a * (v - mv) for a, v in zip(x, values)) / sxx
    score = [a * (v - mv - b * a) for a, v in zip(x, values)]
    var = sum(u * u for u in score)
    for k in range(1, min(lag, n - 1) + 1):
        var += 2 * (1 - k / (lag + 1)) * sum(score[i] * score[i - k] for i in range(k, n))
    return 3600.0 * b, 3600.0 * max(var, 0.0) ** 0.5 / sxx


def main():
    build = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "build")
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, default=3600, help="seconds (default 3600)")
    parser.add_argument("--interval", type=float, default=10, help="seconds between samples")
    parser.add_argument("--domain", type=int, default=91, help="DDS domain (default 91)")
    parser.add_argument("--csv", help="write the samples here")
    parser.add_argument("--monocled", default=os.path.join(build, "service", "monocled"))
    parser.add_argument("--monocle", default=os.path.join(build, "client", "monocle"))
    args = parser.parse_args()
    for path in (args.monocled, args.monocle):
        if not os.access(path, os.X_OK):
            sys.exit(f"soak: {path} is not an executable (build first, or give --monocled/--monocle)")

    state = tempfile.mkdtemp(prefix="monocle-soak-")
    rng = random.Random(62)
    many_points = [f"{rng.uniform(0, 1279):.1f},{rng.uniform(600, 1023):.1f}" for _ in range(20000)]
    live = ["--domain", str(args.domain), "--timeout", "30"]
    service = subprocess.Popen([args.monocled, "--domain", str(args.domain), "--state-dir", state],
                               stdout=subprocess.DEVNULL, stderr=open(os.path.join(state, "log"), "w"))
    clients = [
        [args.monocle, "corner", "locate", "--camera", "sim-corner", "--count", "20"] + live,
        [args.monocle, "status"] + live,
        [args.monocle, "floor", "measure", "--camera", "sim-floor"] + many_points + live,
        [args.monocle, "floor", "measure", "--camera", "sim-floor", "640,900"] + live,
    ]
    rows, failures, start = [], 0, time.monotonic()
    next_sample = start
    try:
        while time.monotonic() - start < args.duration:
            for command in clients:
                run = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True)
                if run.returncode != 0:
                    failures += 1
                    print(f"soak: {' '.join(command[1:4])} failed: {run.stderr.strip()[:200]}",
                          file=sys.stderr)
                if service.poll() is not None:
                    sys.exit(f"soak: monocled exited with {service.returncode} (log {state}/log)")
            now = time.monotonic()
            if now >= next_sample:
                rss, threads, fds, anon, file_backed = sample(service.pid)
                rows.append((now - start, rss, threads, fds, anon, file_backed))
                print(f"{now - start:7.0f} s  RSS {rss:6.1f} MB  threads {threads:3d}  fds {fds:3d}",
                      flush=True)
                next_sample += args.interval
    finally:
        service.send_signal(signal.SIGTERM)
        service.wait(timeout=30)
    if args.csv:
        with open(args.csv, "w") as out:
            out.write("seconds,rss_mb,threads,fds,rss_anon_mb,rss_file_mb\n")
            for row in rows:
                out.write("%.1f,%.2f,%d,%d,%.2f,%.2f\n" % row)
    settled = [r for r in rows if r[0] >= 60] or rows
    times = [r[0] for r in settled]
    lag = max(1, round(300 / args.interval))  # correlations within 5 minutes
    for index, name, unit in ((1, "RSS", "MB"), (4, "RSS anonymous", "MB"),
                              (5, "RSS file-backed", "MB"), (2, "threads", ""),
                              (3, "descriptors", "")):
        values = [r[index] for r in settled]
        slope, sigma = slope_per_hour(times, values, lag)
        print(f"{name}: first {rows[0][index]:.1f} {unit}, after 1 min {values[0]:.1f}, "
              f"last {values[-1]:.1f}, min {min(values):.1f}, max {max(values):.1f}, "
              f"slope {slope:+.2f} ± {sigma:.2f} {unit}/h".replace("  ", " "))
    print(f"{len(rows)} samples over {rows[-1][0]:.0f} s, {failures} client failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
