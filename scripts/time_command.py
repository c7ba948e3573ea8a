#!/usr/bin/env python3
"""A compiler and linker launcher that logs each command's CPU and wall time (scripts/build_times.sh).

CMake runs `time_command.py LOG COMPILER ARGS...` for every compile and link
(CMAKE_CXX_COMPILER_LAUNCHER, CMAKE_CXX_LINKER_LAUNCHER). The command runs unchanged, with its
exit status and output; one line is appended to LOG:

    kind <TAB> output <TAB> user_s <TAB> sys_s <TAB> wall_s <TAB> max_rss_kib

kind is `compile` (the command has -c) or `link`; output is the argument of -o, relative to the
build folder. The times are the command's own and its children's (cc1plus, as, collect2, ld), from
wait4's resource usage, so a busy machine changes the wall column but hardly the CPU columns.
"""
import os
import sys
import time


def output_of(args):
    """The -o argument of a compiler command line ("?" if there is none)."""
    for i, a in enumerate(args[:-1]):
        if a == "-o":
            return args[i + 1]
    return "?"


def main():
    if len(sys.argv) < 3:
        sys.stderr.write("usage: time_command.py LOG COMMAND [ARGS...]\n")
        return 2
    log, command = sys.argv[1], sys.argv[2:]
    start = time.monotonic()
    pid = os.fork()
    if pid == 0:
        try:
            os.execvp(command[0], command)
        except OSError as e:
            sys.stderr.write(f"time_command.py: cannot run {command[0]}: {e}\n")
            os._exit(127)
    _, status, usage = os.wait4(pid, 0)
    wall = time.monotonic() - start
    kind = "compile" if "-c" in command else "link"
    line = (f"{kind}\t{output_of(command)}\t{usage.ru_utime:.3f}\t{usage.ru_stime:.3f}\t"
            f"{wall:.3f}\t{usage.ru_maxrss}\n")
    # one write per line with O_APPEND: parallel jobs never interleave inside a line
    fd = os.open(log, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        os.write(fd, line.encode())
    finally:
        os.close(fd)
    return os.waitstatus_to_exitcode(status)


if __name__ == "__main__":
    code = main()
    sys.exit(code if code >= 0 else 128 - code)
