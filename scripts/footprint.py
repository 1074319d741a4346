#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The firmware footprint report, from the build trees scripts/footprint
made (fw-TARGET-float: float, -Os): the flash of each minimal image of
firmware/min_image.c over the base image, per target, with the flash
targets stated met or not; the worst-case stack depth of every public
function against the stack target of its target; per module
.text/.rodata/.data/.bss and sizeof of the public structs; and what the
KF2-alone and EKF3-alone images consist of, function by function
(Cortex-M4F). Prints Markdown; --docs FILE splices the first part into FILE
between its firmware:footprint markers and the per-function tables between
its firmware:flash markers.

Stack depth, counted with every jump as a call: depth(f) = frame(f) + the
deepest depth of what f calls or jumps to, whether or not f has released
its frame before a jump (a tail call). The core's frames and edges are
gcc's -fcallgraph-info=su (.ci): it is written from the final code, so it
names tail calls and the library calls gcc emits itself (soft float,
memcpy and memset for block copies) as well as the calls in the source.
libm, libc and libgcc come without .ci (Debian builds them without it),
so their frames are read from the prologues of their disassembly
(push/vpush/sub sp on Arm, addi sp on RISC-V) and their edges from its call
and jump relocations. The only indirect calls are the filters' model
callbacks: counted as EKF3's built-in models of the kind the public step
calls (measurement models in updates, motion models in predictions).
"""
import argparse
import datetime
import glob
import os
import re
import subprocess
import sys

TARGETS = [
    ("cortex-m4f", "Cortex-M4F", "arm-none-eabi-"),
    ("cortex-m0plus", "Cortex-M0+", "arm-none-eabi-"),
    ("riscv32", "RV32IMAFC", "riscv64-unknown-elf-"),
]
# The minimal images (firmware/min_image.c), each measured against
# gf_fw_base.
IMAGES = [
    ("kf2", "KF2 alone"),
    ("ekf3", "EKF3 alone (built-in models)"),
    ("kf4", "`gf_kf`, n = 4, m = 2 alone"),
    ("kf2_ekf3", "KF2 + EKF3"),
]
# Flash targets (bytes over the base image), per (image, target).
FLASH_TARGETS = {
    ("kf2", "cortex-m4f"): 3 * 1024,
    ("ekf3", "cortex-m4f"): 4608,
    ("kf4", "cortex-m4f"): 5 * 1024,
    ("kf2_ekf3", "cortex-m4f"): 6 * 1024,
    ("kf2", "cortex-m0plus"): 6 * 1024,
}
# Stack target of every public function, per target.
STACK_TARGETS = {"cortex-m4f": 320, "cortex-m0plus": 448, "riscv32": 320}
# The modules: every src/*.c the build compiled, in this order first.
MODULE_ORDER = ["ldl", "udu", "mat", "cov2", "kf2", "ekf3", "kf", "ekf",
                "status", "rng", "if2", "ukf3", "pf3"]
STRUCTS = ["gf_kf2", "gf_ekf3", "gf_kf2_model", "gf_kf2_meas",
           "gf_ekf3_motion", "gf_ekf3_meas", "gf_innovation", "gf_ellipse",
           "gf_vec2", "gf_vec3", "gf_mat2", "gf_mat3",
           "gf_if2", "gf_ukf3", "gf_ukf3_params", "gf_pf3", "gf_pf3_particle",
           "gf_rng"]
# What a model callback runs, by the kind of step (model_kind).
MODELS = {"meas": {"gf_ekf3_meas_x", "gf_ekf3_meas_xy"},
          "motion": {"gf_ekf3_motion_forward_turn"}}
# A double-precision libm function or soft-double helper in a float image
# means a float was promoted somewhere.
DOUBLE_SYMS = re.compile(
    r"^(sin|cos|tan|sqrt|atan2|atan|ceil|floor|log|exp|fabs|pow|"
    r"__ieee754_\w+[^f]|__kernel_(sin|cos|rem_pio2)|__aeabi_d\w+|"
    r"__(add|sub|mul|div|extendsf|truncdf)\w*df\w*)$")


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True,
                          text=True).stdout


def section_kind(name):
    for prefix, kind in ((".text", "text"), (".rodata", "rodata"),
                         (".srodata", "rodata"), (".data", "data"),
                         (".sdata", "data"), (".bss", "bss"),
                         (".sbss", "bss")):
        if name == prefix or name.startswith(prefix + "."):
            return kind
    return None


def core_archive(build):
    return os.path.join(build, "gaussfilt/libgaussfilt.a")




def core_objects(prefix, build):
    """The core's objects ("kf2.c", ...): those of its archive (a build tree
    may still hold the files of sources since removed)."""
    return [m[:-len(".obj")] for m in
            run([prefix + "ar", "t", core_archive(build)]).split()
            if m.endswith(".c.obj")]


def object_path(build, obj):
    return os.path.join(build, "gaussfilt/CMakeFiles/gaussfilt.dir/src", obj)


def module_sizes(prefix, build):
    """{module: {text, rodata, data, bss}} from the objects' sections."""
    sizes = {}
    objs = sorted(core_objects(prefix, build), key=lambda o: (
        MODULE_ORDER.index(o[:-2]) if o[:-2] in MODULE_ORDER else 99, o))
    for obj in objs:
        acc = {"text": 0, "rodata": 0, "data": 0, "bss": 0}
        out = run([prefix + "size", "-A", object_path(build, obj + ".obj")])
        for line in out.splitlines():
            parts = line.split()
            if len(parts) >= 2 and parts[1].isdigit():
                kind = section_kind(parts[0])
                if kind:
                    acc[kind] += int(parts[1])
        sizes[obj[:-2]] = acc
    return sizes


def struct_sizes(prefix, build):
    objs = glob.glob(os.path.join(build, "CMakeFiles/gf_fw_sizes.dir/*.obj"))
    out = {}
    for line in run([prefix + "nm", "-S", objs[0]]).splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[3].startswith("gf_sizeof_"):
            out[parts[3][len("gf_sizeof_"):]] = int(parts[1], 16)
    return out



# ---- stack ------------------------------------------------------------------

CI_NODE = re.compile(r'node: \{ title: "([^"]+)" label: "[^"]*\\n(\d+) '
                     r'bytes \(([^)]+)\)"')
CI_EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')


def ci_name(title):
    """A static function's title is its source's path and its name: kept
    as "kf2.c:kf2_update_step", unique and short."""
    return os.path.basename(title).replace("__builtin_", "")


def read_ci(build, objects):
    """({function: frame}, {function: callees}) of the core's .ci files."""
    frames, edges = {}, {}
    for obj in objects:
        text = open(object_path(build, obj + ".ci")).read()
        for title, size, kind in CI_NODE.findall(text):
            if kind != "static":
                sys.exit(f"{obj}: {ci_name(title)} has a {kind} frame")
            frames[ci_name(title)] = int(size)
        for src, dst in CI_EDGE.findall(text):
            edges.setdefault(ci_name(src), set()).add(ci_name(dst))
    return frames, edges




ARM_REG_LIST = re.compile(r"\{([^}]*)\}")


def count_regs(lst, width):
    n = 0
    for item in lst.split(","):
        item = item.strip()
        if "-" in item:
            a, b = item.split("-")
            n += int(b[1:]) - int(a[1:]) + 1
        elif item:
            n += 1
    return n * width


def prologue_frame(insns, arm):
    """Deepest sp decrement reached along the function's code, in order
    (push/vpush/sub sp on Arm, addi sp on RISC-V; pops and adds give it
    back): shrink-wrapped prologues after an early return are counted."""
    cur = best = 0
    for text in insns:
        parts = text.split(None, 1)
        if not parts:
            continue
        op, args = parts[0], parts[1] if len(parts) > 1 else ""
        delta = 0
        if arm:
            lst = ARM_REG_LIST.search(args)
            if op in ("push", "push.w") or (op == "stmdb" and
                                             args.startswith("sp!")):
                delta = count_regs(lst.group(1), 4)
            elif op in ("pop", "pop.w") or (op == "ldmia" and
                                             args.startswith("sp!")):
                delta = -count_regs(lst.group(1), 4)
            elif op in ("vpush", "vstmdb", "vpop", "vldmia") and lst and \
                    (op in ("vpush", "vpop") or args.startswith("sp!")):
                regs = lst.group(1)
                n = count_regs(regs, 8 if "d" in regs else 4)
                delta = n if op in ("vpush", "vstmdb") else -n
            elif op in ("sub", "sub.w", "subw", "add", "add.w", "addw") and \
                    re.match(r"^sp, (sp, )?#\d+$", args):
                n = int(args.split("#")[1])
                delta = n if op.startswith("sub") else -n
        else:
            m = re.match(r"^sp,sp,(-?\d+)$", args)
            if op in ("addi", "add", "c.addi", "c.addi16sp") and m:
                delta = -int(m.group(1))
        cur = max(0, cur + delta)
        best = max(best, cur)
    return best




# Calls and jumps to other functions, by their relocations.
CALL_RELOCS = re.compile(r"R_(ARM_THM_CALL|ARM_CALL|ARM_THM_JUMP24|"
                         r"ARM_JUMP24|RISCV_CALL|RISCV_CALL_PLT|RISCV_JAL)\s+"
                         r"([\w.$]+)")



# Calls and jumps to other functions, by their relocations.
CALL_RELOCS = re.compile(r"R_(ARM_THM_CALL|ARM_CALL|ARM_THM_JUMP24|"
                         r"ARM_JUMP24|RISCV_CALL|RISCV_CALL_PLT|RISCV_JAL)\s+"
                         r"([\w.$]+)")
# picolibc's -Os code saves registers through libgcc's millicode: on rv32,
# `jal t0, __riscv_save_N` moves sp by 16 bytes per group of four registers
# before the prologue's own adjustment, for as long as the function runs.
RISCV_MILLICODE = re.compile(r"^__riscv_(save|restore)_(\d+)$")


def disassemble(prefix, archive):
    """{function: (frame, callees)} of a library archive: the frame from
    the prologue, the callees every function it calls or jumps to (by
    relocation, or the direct bl/b/jal/j the assembler resolved itself)."""
    arm = prefix.startswith("arm")
    out = run([prefix + "objdump", "-dr", "--no-show-raw-insn", archive])
    funcs, aliases = {}, {}
    name, section_fn, insns, callees = None, None, [], set()

    def flush():
        if not name:
            return
        save = max([16 * (int(m.group(2)) // 4 + 1) for m in
                    map(RISCV_MILLICODE.match, callees)
                    if m and m.group(1) == "save"] or [0])
        new = (prologue_frame(insns, arm) + save,
               {c for c in callees - {name} if not RISCV_MILLICODE.match(c)})
        if name not in funcs or new[0] > funcs[name][0]:
            funcs[name] = new

    for line in out.splitlines():
        m = re.match(r"^Disassembly of section \.text\.([\w$]+):$", line)
        if m:
            section_fn = m.group(1)
            continue
        m = re.match(r"^[0-9a-f]+ <([\w.$]+)>:$", line)
        if m and not m.group(1).startswith(".L"):
            flush()
            name, insns, callees = m.group(1), [], set()
            # picolibc labels cosf's code _cosf; its section says cosf.
            if section_fn and section_fn != name:
                aliases[name] = section_fn
            section_fn = None
            continue
        if m or name is None:
            continue
        m = CALL_RELOCS.search(line)
        if m:
            if not m.group(2).startswith(".L"):
                callees.add(m.group(2))
            continue
        m = re.match(r"^\s+[0-9a-f]+:\s+(.*)$", line)
        if not m or m.group(1).startswith("R_"):
            continue  # not an instruction (other relocations: RELAX, ...)
        text = re.split(r"[@;]" if arm else r"[#;]", m.group(1))[0].strip()
        insns.append(text)
        op, args = (text.split(None, 1) + [""])[:2]
        bm = re.match(r"^(ra,)?[0-9a-f]+ <([\w.$]+)>$", args)
        if bm and not bm.group(2).startswith(".L") and op in (
                "bl", "blx", "b", "b.w", "b.n", "jal", "j"):
            callees.add(bm.group(2))
    flush()
    for a, n in aliases.items():
        funcs.setdefault(n, funcs[a])
    return funcs


def libraries(build):
    """The C library, libm and libgcc archives the minimal images linked."""
    libs = []
    for line in open(os.path.join(build, "gf_fw_kf2_ekf3.map")):
        m = re.match(r"^LOAD (\S+/lib(c|m|gcc|c_nano|m_nano)\.a)$", line)
        if m and m.group(1) not in libs:
            libs.append(os.path.normpath(m.group(1)))
    return libs




def plain(name):
    """A public function's name without its link suffix (names.h)."""
    return re.sub(r"^(gf_\w+)_f(32|64)$", r"\1", name)


def api_functions(root):
    """The functions the public headers declare."""
    names = set()
    for h in glob.glob(os.path.join(root, "include/gaussfilt/*.h")):
        names |= set(re.findall(r"\b(gf_\w+)\s*\(", open(h).read()))
    return names


def model_kind(name):
    """The models a public function's callbacks run: motion models in
    predictions, measurement models in updates, either elsewhere."""
    if re.search(r"predict|motion", name):
        return "motion"
    if re.search(r"update|meas", name):
        return "meas"
    return None


def call_depths(prefix, build, frames, edges, names):
    """({function of names: (frame, depth, chain)}, functions without a
    known frame): depth through the deepest chain of calls and jumps, over
    the frames and edges given and the C library's, libm's and libgcc's."""
    lib = {}
    for archive in libraries(build):
        for k, v in disassemble(prefix, archive).items():
            lib.setdefault(k, v)
    models = {kind: {n for n in frames if plain(n) in names}
              for kind, names in MODELS.items()}
    models[None] = models["meas"] | models["motion"]
    unknown = set()

    def frame(n):
        if n in frames:
            return frames[n]
        if n in lib:
            return lib[n][0]
        unknown.add(n)
        return 0

    def callees(n, kind):
        c = set(edges.get(n, ()) if n in frames else lib.get(n, (0, ()))[1])
        if "__indirect_call" in c:
            c = (c - {"__indirect_call"}) | models[kind]
        return c - {n}

    memo = {}

    def depth(n, kind, path=()):
        """(depth, deepest callee)"""
        if n in path:
            sys.exit("recursion: " + " -> ".join(path + (n,)))
        if (n, kind) not in memo:
            best, via = frame(n), None
            for c in sorted(callees(n, kind)):
                d = frame(n) + depth(c, kind, path + (n,))[0]
                if d > best:
                    best, via = d, c
            memo[(n, kind)] = (best, via)
        return memo[(n, kind)]

    rows = {}
    for n in sorted(frames):
        if ":" in n or plain(n) not in names:
            continue
        kind = model_kind(plain(n))
        d, via = depth(n, kind)
        chain = plain(n)
        while via:
            chain += " → " + plain(via)
            via = memo[(via, kind)][1]
        rows[plain(n)] = (frames[n], d, chain)
    return rows, unknown


def stack_report(prefix, build, api):
    """({public function: (frame, depth, chain)}, functions without a
    known frame)."""
    frames, edges = read_ci(build, core_objects(prefix, build))
    return call_depths(prefix, build, frames, edges, api)


# The loop floor's steps (bench/floor.h) whose depth the report prints,
# with the library's public function each stands for.
FLOOR_STEPS = [
    ("floor_kf2_predict", "gf_kf2_predict"),
    ("floor_kf2_update", "gf_kf2_update"),
    ("floor_kf2_update_api", "gf_kf2_update"),
    ("floor_ekf3_predict", "gf_ekf3_predict"),
    ("floor_ekf3_update", "gf_ekf3_update"),
    ("floor_ekf3_update_api", "gf_ekf3_update"),
]


def floor_stack(prefix, build):
    """{floor step: (frame, depth, chain)} of the loop floor the firmware
    build compiled (gf_fw_floor, with its .ci files), on the core's frames
    for what it calls of the core (the angle wrap, the built-in models)."""
    frames, edges = read_ci(build, core_objects(prefix, build))
    for ci in sorted(glob.glob(os.path.join(
            build, "CMakeFiles/gf_fw_floor.dir/**/*.ci"), recursive=True)):
        text = open(ci).read()
        for title, size, kind in CI_NODE.findall(text):
            frames[ci_name(title)] = int(size)
        for src, dst in CI_EDGE.findall(text):
            edges.setdefault(ci_name(src), set()).add(ci_name(dst))
    return call_depths(prefix, build, frames, edges,
                       {f for f, _ in FLOOR_STEPS})[0]


# ---- images -----------------------------------------------------------------

def image_sizes(prefix, elf):
    text, data, bss = run([prefix + "size", elf]).splitlines()[1].split()[:3]
    return int(text), int(data), int(bss)


def flash(sizes):
    """Flash of an image: text (and rodata) + the data's initial values."""
    return sizes[0] + sizes[1]


# Output sections that take no flash: not loaded, or zero-initialised RAM.
NOT_LOADED = (".debug", ".comment", ".ARM.attributes", ".riscv.attributes",
              ".stab", ".note", ".gnu", ".bss", ".sbss", ".tbss", ".noinit",
              ".heap", ".stack")


def map_sections(mapfile):
    """The loaded input sections of an image: (address, size, origin), the
    origin one of core, libm, libc, libgcc, app."""
    out = []
    text = open(mapfile).read()
    text = text[text.index("Linker script and memory map"):]
    pending, out_sect = None, ""
    for line in text.splitlines():
        m = re.match(r"^(\.[\w.$]+)\b", line)
        if m:
            out_sect = m.group(1)
            continue
        m = re.match(r"^ (\.[\w.$]+|COMMON)\s*$", line)
        if m:
            pending = m.group(1)
            continue
        m = re.match(r"^ (\.[\w.$]+|COMMON)?\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)"
                     r"\s+(\S+)$", line)
        if not m:
            pending = None
            continue
        sect = m.group(1) or pending
        pending = None
        addr, size = int(m.group(2), 16), int(m.group(3), 16)
        origin = m.group(4)
        if not sect or size == 0 or sect == "COMMON" or \
                out_sect.startswith(NOT_LOADED):
            continue
        if "libgaussfilt.a" in origin:
            key = "core"
        elif re.search(r"/libm(_nano)?\.a\(", origin):
            key = "libm"
        elif re.search(r"/libgcc\.a\(", origin):
            key = "libgcc"
        elif re.search(r"/libc(_nano)?\.a\(", origin):
            # picolibc keeps libm inside libc.a
            key = "libm" if "libm_" in origin else "libc"
        else:
            key = "app"
        out.append((addr, size, key))
    return out


def map_breakdown(mapfile):
    """Bytes per origin (core, libm, libc, libgcc, app) in the image."""
    acc = {}
    for _, size, key in map_sections(mapfile):
        acc[key] = acc.get(key, 0) + size
    return acc


def image_symbols(prefix, build, img):
    """{name: (size, origin)} of the sized symbols an image holds in
    flash (code, constants, initialised data), link suffix _f32 dropped."""
    elf = os.path.join(build, f"gf_fw_{img}.elf")
    sections = map_sections(os.path.join(build, f"gf_fw_{img}.map"))
    out = {}
    for line in run([prefix + "nm", "-S", "--size-sort", elf]).splitlines():
        parts = line.split()
        if len(parts) != 4 or parts[2] not in "TtRrDdWw":
            continue
        addr, size, name = int(parts[0], 16), int(parts[1], 16), parts[3]
        origin = next((k for a, s, k in sections if a <= addr < a + s), "?")
        out[re.sub(r"_f32$", "", name)] = (size, origin)
    return out


def image_functions(prefix, build, img):
    """The symbols an image adds to the base image: (name, size, origin);
    main by how much it grew."""
    base = image_symbols(prefix, build, "base")
    syms = image_symbols(prefix, build, img)
    out = {}
    for n, (size, origin) in syms.items():
        if n not in base:
            out[n] = (size, origin)
        elif n == "main" and size != base[n][0]:
            out["main (the calls)"] = (size - base[n][0], "app")
    return out


def kib(b):
    return f"{b / 1024:.2f} KiB"


def fmt_b(b):
    return f"{b:,} B"



def report(root, build_root):
    today = datetime.date.today().isoformat()
    versions = [f"`{run([p + 'gcc', '--version']).splitlines()[0]}`"
                for p in ("arm-none-eabi-", "riscv64-unknown-elf-")]
    lines = [f"Generated by `scripts/footprint --docs` on {today} with "
             + " and ".join(versions)
             + "; `-Os`, float build (`gf_real` = float), "
             "`-ffunction-sections -fdata-sections`, `--gc-sections`.", ""]

    api = api_functions(root)
    results = {}
    for key, label, pfx in TARGETS:
        build = os.path.join(build_root, f"fw-{key}-float")
        imgs = ["base"] + [img for img, _ in IMAGES] + [
            f"floor_{img}" for img, _ in IMAGES]
        results[key] = {
            "label": label,
            "mods": module_sizes(pfx, build),
            "structs": struct_sizes(pfx, build),
            "stack": stack_report(pfx, build, api),
            "floor": floor_stack(pfx, build),
            "images": {img: image_sizes(pfx, os.path.join(
                build, f"gf_fw_{img}.elf")) for img in imgs},
            "bd": {img: map_breakdown(os.path.join(
                build, f"gf_fw_{img}.map")) for img in imgs},
            "syms": run([pfx + "nm", os.path.join(build,
                                                  "gf_fw_kf2_ekf3.elf")]),
        }
    m4 = results["cortex-m4f"]
    met = lambda ok: "**met**" if ok else "**NOT met**"  # noqa: E731
    labels = [results[k]["label"] for k, _, _ in TARGETS]

    def delta(key, img):
        ims = results[key]["images"]
        return flash(ims[img]) - flash(ims["base"])

    # Flash per image and target.
    lines += ["Flash each minimal image adds to the base image "
              "(`firmware/min_image.c`: init, predict, update and the cov "
              "accessor of its filters, inputs and outputs volatile; the base "
              "image has the same start-up and I/O and no filter), text + "
              "data, C library, libm and libgcc included:", "",
              "| image | " + " | ".join(labels) + " |",
              "|---|" + "---|" * len(TARGETS)]

    def image_rows(cell):
        """A row per image, cell(image, target key) in each column."""
        return [f"| {label} | " + " | ".join(
            cell(img, key) for key, _, _ in TARGETS) + " |"
            for img, label in IMAGES]

    def flash_cell(img, key):
        d = delta(key, img)
        lim = FLASH_TARGETS.get((img, key))
        cell = f"{fmt_b(d)} ({kib(d)})"
        if lim is not None:
            cell += f"; target {kib(lim)}: {met(d <= lim)}"
        return cell

    lines += image_rows(flash_cell)
    lines.append("| base image (absolute) | " + " | ".join(
        fmt_b(flash(results[k]["images"]["base"])) for k, _, _ in TARGETS)
        + " |")
    lines.append("")

    # The loop floor in the same images.
    lines += ["The loop floor (`bench/floor.c`, `bench/floor_core.c`: the "
              "least code that keeps the filters' promises in the core's loop "
              "style, less the features [Against the loop floor]"
              "(#against-the-loop-floor) accounts for) in the same images "
              "(`GF_FW_FLOOR`), flash over the base image:", "",
              "| image | " + " | ".join(labels) + " |",
              "|---|" + "---|" * len(TARGETS)]
    lines += image_rows(lambda img, key: fmt_b(delta(key, f"floor_{img}")))
    lines.append("")

    lines += ["What the delta is made of, Cortex-M4F (bytes, from the link "
              "map; per function: [where the flash goes]"
              "(#where-the-flash-goes)):", "",
              "| image | delta | core | libm | libc | libgcc | `main`'s calls "
              "and models |", "|---|---|---|---|---|---|---|"]
    for img, label in IMAGES:
        bd, bb = m4["bd"][img], m4["bd"]["base"]
        part = lambda k: bd.get(k, 0) - bb.get(k, 0)  # noqa: E731
        lines.append(f"| {label} | {delta('cortex-m4f', img)} | "
                     f"{part('core')} | {part('libm')} | {part('libc')} | "
                     f"{part('libgcc')} | {part('app')} |")
    lines.append("")

    dbl = sorted({ln.split()[-1] for ln in m4["syms"].splitlines()
                  if DOUBLE_SYMS.match(ln.split()[-1])})
    lines += ["Double promoted in the float KF2 + EKF3 image (Cortex-M4F): "
              + (", ".join(f"`{s}`" for s in dbl) if dbl else "none (no "
                 "double libm function, no soft-double helper)") + ".", ""]

    # Stack.
    lines += ["Stack: the deepest public function per target, counted with "
              "every jump as a call:", "",
              "| target | target depth | deepest public function | depth | "
              "| public functions over the target |",
              "|---|---|---|---|---|---|"]
    for key, label, _ in TARGETS:
        rows = results[key]["stack"][0]
        lim = STACK_TARGETS[key]
        d, n = max((d, n) for n, (_, d, _) in rows.items())
        over = sorted(n for n, (_, dd, _) in rows.items() if dd > lim)
        lines.append(f"| {label} | {lim} B | `{n}` | {d} B | {met(d <= lim)}"
                     " | " + (", ".join(f"`{o}` ({rows[o][1]})" for o in over)
                              if over else "none") + " |")
    lines.append("")

    lines += ["Worst-case stack depth of every public function (bytes: own "
              "frame / depth, the depth being the frame plus the deepest of "
              "what the function calls or jumps to, libm, libc and libgcc "
              "included, a jump counted like a call; **!**: over the "
              "target). Model callbacks are counted as EKF3's built-in "
              "models: a measurement model in updates, a motion model in "
              "predictions; a model of your own adds max(0, its depth - the "
              "built-in's).", "",
              "| function | " + " | ".join(labels)
              + " | deepest chain (Cortex-M4F) |",
              "|---|" + "---|" * len(TARGETS) + "---|"]
    for n in sorted(m4["stack"][0]):
        cells = []
        for key, _, _ in TARGETS:
            f, d, _ = results[key]["stack"][0][n]
            flag = " **!**" if d > STACK_TARGETS[key] else ""
            cells.append(f"{f} / {d}{flag}")
        lines.append(f"| `{n}` | " + " | ".join(cells)
                     + f" | {m4['stack'][0][n][2]} |")
    lines.append("")
    lines += ["The loop floor's stack (`bench/floor_core.c`, `bench/floor.c`, "
              "compiled as the core is and counted the same way; "
              "`*_update_api`: the floor's update with what the library's "
              "update must also hold, `bench/floor.h`), beside the library's "
              "function it stands for (frame / depth, bytes; **!**: over "
              "the target):", "",
              "| floor step | " + " | ".join(labels)
              + " | the library's |", "|---|" + "---|" * len(TARGETS) + "---|"]
    for fl, lib_fn in FLOOR_STEPS:
        cells = []
        for key, _, _ in TARGETS:
            f, d, _ = results[key]["floor"].get(fl, (0, 0, ""))
            flag = " **!**" if d > STACK_TARGETS[key] else ""
            cells.append(f"{f} / {d}{flag}")
        lines.append(f"| `{fl}` | " + " | ".join(cells) + " | " + " / ".join(
            str(results[k]["stack"][0][lib_fn][1]) for k, _, _ in TARGETS)
            + f" (`{lib_fn}`) |")
    lines.append("")
    unknown = [f"{results[k]['label']}: "
               + ", ".join(f"`{u}`" for u in sorted(results[k]["stack"][1]))
               for k, _, _ in TARGETS if results[k]["stack"][1]]
    if unknown:
        lines += ["No frame found (counted as 0): " + "; ".join(unknown)
                  + ".", ""]

    # Modules.
    lines += ["Library objects, per module (bytes; `.data` and `.bss` must "
              "stay 0: the core has no globals):", "",
              "| module | " + " | ".join(
                  f"{lb} .text / .rodata / .data / .bss" for lb in labels)
              + " |", "|---|" + "---|" * len(TARGETS)]
    zero = {"text": 0, "rodata": 0, "data": 0, "bss": 0}
    for mod in list(m4["mods"]) + ["total"]:
        cells = []
        for key, _, _ in TARGETS:
            mods = results[key]["mods"]
            s = {k: sum(m[k] for m in mods.values()) for k in zero} \
                if mod == "total" else mods.get(mod, zero)
            cells.append(f"{s['text']} / {s['rodata']} / {s['data']} / "
                         f"{s['bss']}")
        name = f"`{mod}.c`" if mod != "total" else "**total**"
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines.append("")

    # Structs.
    lines += ["`sizeof` of the public structs (bytes, float build; the double "
              "build doubles every `gf_real`):", "",
              "| struct | " + " | ".join(labels) + " |",
              "|---|" + "---|" * len(TARGETS)]
    for st in STRUCTS:
        lines.append(f"| `{st}` | " + " | ".join(
            str(results[k]["structs"].get(st, "-")) for k, _, _ in TARGETS)
            + " |")
    return "\n".join(lines) + "\n", functions_report(build_root, results)


def functions_report(build_root, results):
    """The KF2-alone and EKF3-alone images on Cortex-M4F, function by
    function: what each adds to the base image."""
    pfx = "arm-none-eabi-"
    build = os.path.join(build_root, "fw-cortex-m4f-float")
    kf2 = image_functions(pfx, build, "kf2")
    ekf3 = image_functions(pfx, build, "ekf3")
    both = set(kf2) & set(ekf3)

    def key(n):
        size = max(kf2.get(n, (0,))[0], ekf3.get(n, (0,))[0])
        return (n not in both, -size, n)

    ims = results["cortex-m4f"]["images"]
    d = {img: flash(ims[img]) - flash(ims["base"]) for img in ("kf2", "ekf3")}
    lines = ["What the KF2-alone and EKF3-alone images add to the base image "
             "on the Cortex-M4F, symbol by symbol (`nm --size-sort` of each "
             "image, the symbols the base image does not have; bytes; "
             "link suffix `_f32` dropped). Symbols in both images first: "
             "the shared core and what it takes from the C library.", "",
             "| symbol | from | KF2 alone | EKF3 alone |",
             "|---|---|---|---|"]
    for n in sorted(set(kf2) | set(ekf3), key=key):
        origin = (kf2.get(n) or ekf3.get(n))[1]
        cell = lambda t: str(t[n][0]) if n in t else ""  # noqa: E731
        lines.append(f"| `{n}` | {origin} | {cell(kf2)} | {cell(ekf3)} |")
    shared = {img: sum(t[n][0] for n in both if t[n][1] == "core")
              for img, t in (("kf2", kf2), ("ekf3", ekf3))}
    listed = {img: sum(s for s, _ in t.values())
              for img, t in (("kf2", kf2), ("ekf3", ekf3))}
    lines += [f"| **the core functions in both images** | core | "
              f"{shared['kf2']} | {shared['ekf3']} |",
              f"| **listed** | | {listed['kf2']} | {listed['ekf3']} |",
              f"| alignment and unnamed constants | | "
              f"{d['kf2'] - listed['kf2']} | {d['ekf3'] - listed['ekf3']} |",
              f"| **delta flash** | | {d['kf2']} | {d['ekf3']} |", ""]
    for img, label, t in (("kf2", "KF2 alone", kf2),
                          ("ekf3", "EKF3 alone", ekf3)):
        lim = FLASH_TARGETS[(img, "cortex-m4f")]
        lines.append(f"- {label}: {d[img]} B against {lim} B: the core "
                     f"functions it shares with the other image are "
                     f"{shared[img]} B of it, "
                     f"{100 * shared[img] / d[img]:.0f}%"
                     + (f", {shared[img] - lim:+d} B against the target "
                        "on their own." if shared[img] > lim else "."))
    return "\n".join(lines) + "\n"


MARKERS = {
    "footprint": ("<!-- firmware:footprint:begin -->",
                  "<!-- firmware:footprint:end -->"),
    "flash": ("<!-- firmware:flash:begin -->",
              "<!-- firmware:flash:end -->"),
}


def splice(doc, parts):
    s = open(doc).read()
    for name, text in parts.items():
        begin, end = MARKERS[name]
        if begin not in s or end not in s:
            sys.exit(f"{doc}: no {begin} / {end} lines")
        s = s[:s.index(begin)] + f"{begin}\n{text}{end}" + \
            s[s.index(end) + len(end):]
    open(doc, "w").write(s)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--docs", metavar="FILE")
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    text, funcs = report(root, args.build)
    print(text)
    print(funcs)
    if args.docs:
        splice(args.docs, {"footprint": text, "flash": funcs})


if __name__ == "__main__":
    main()
