#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Where the instructions of each report of the Cortex-M4F benchmark image
go, by function: reads the image's output (its "bench WL PART N" lines)
and the insncount plugin's log of a profile=on run (bench/qemu/m4f.sh,
gf_m4f_count with a profile file), maps every counted address to the
function that holds it (arm-none-eabi-nm), and prints per report the
functions' own instructions per region (self, not inclusive), largest
first, with their VDIV.F32 / VSQRT.F32 counts read from the disassembly.

    profile.py ELF IMAGE_OUTPUT PLUGIN_LOG
"""
import bisect
import re
import subprocess
import sys


def symbols(elf):
    out = subprocess.run(["arm-none-eabi-nm", "-n", "--defined-only", elf],
                         check=True, capture_output=True, text=True).stdout
    addrs, names = [], []
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "Tt" and not parts[2].startswith("$"):
            addrs.append(int(parts[0], 16) & ~1)
            names.append(parts[2])
    return addrs, names


def special(elf):
    """{address: "div" | "sqrt"} of the VDIV.F32 / VSQRT.F32 in the image."""
    out = subprocess.run(["arm-none-eabi-objdump", "-d", "--no-show-raw-insn",
                          elf], check=True, capture_output=True,
                         text=True).stdout
    kinds = {}
    # In an IT block: vdivgt.f32 and the like.
    for m in re.finditer(r"^\s*([0-9a-f]+):\s+(vdiv|vsqrt)"
                         r"(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le)?"
                         r"\.f32", out, re.M):
        kinds[int(m.group(1), 16)] = "div" if m.group(2) == "vdiv" else "sqrt"
    return kinds


def main():
    elf, image_out, log = sys.argv[1:4]
    addrs, names = symbols(elf)
    kinds = special(elf)
    labels = [ln.split()[1:] for ln in open(image_out)
              if ln.startswith("bench ") and ln.strip() != "bench done"]
    reports, pcs = [], {}
    for ln in open(log):
        m = re.match(r"^insncount: pc 0x([0-9a-f]+) (\d+)$", ln)
        if m:
            pcs[int(m.group(1), 16)] = int(m.group(2))
        elif ln.startswith("insncount: regions"):
            reports.append((int(ln.split()[2]), pcs))
            pcs = {}
    if len(reports) != len(labels):
        sys.exit(f"{len(reports)} reports for {len(labels)} labels")
    for (wl, part, _), (regions, pcs) in zip(labels, reports):
        if wl == "empty":
            continue
        by = {}
        for pc, n in pcs.items():
            i = bisect.bisect_right(addrs, pc) - 1
            f = names[i] if i >= 0 else "?"
            e = by.setdefault(f, [0, 0, 0])
            e[0] += n
            if kinds.get(pc) == "div":
                e[1] += n
            elif kinds.get(pc) == "sqrt":
                e[2] += n
        total = sum(e[0] for e in by.values())
        print(f"{wl} {part}: {total / regions:.1f} instructions per region "
              f"(the markers' 1 included)")
        for f, (n, d, s) in sorted(by.items(), key=lambda kv: -kv[1][0]):
            extra = ""
            if d or s:
                extra = f"  div {d / regions:.3g} sqrt {s / regions:.3g}"
            print(f"  {n / regions:9.1f}  {100 * n / total:5.1f}%  {f}{extra}")
        print()


if __name__ == "__main__":
    main()
