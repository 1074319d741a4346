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

Stack depth: a function's own frame is gcc's -fstack-usage figure (.su)
for the core and, for what the core calls in libm, libc and libgcc (which
Debian builds without -fstack-usage), the frame read from the prologue of
its disassembly (push/vpush/sub sp on Arm, addi sp on RISC-V). The depth is
a walk over the call graph: depth(f) = frame(f) + the deepest depth of
what f calls or jumps to. Every jump to another function counts as a call,
its frame on top of the caller's, whether or not the caller has released
its frame by then. The edges are gcc's -fcallgraph-info (.ci) plus the call
and jump relocations of the disassembly: .ci is written before gcc expands
library calls of its own (libgcc's soft-float helpers, memcpy and memset
for block copies), and libm, libc and libgcc have no .ci at all. The only
indirect calls are EKF3's model callbacks; they are counted as the deepest
built-in model (see CALLBACKS).
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
# Indirect calls: which functions a callback slot runs when the built-in
# models are used (static functions named with their object, qualify).
CALLBACKS = {
    "ekf3.c:ekf3_predict_step": ["gf_ekf3_motion_forward_turn"],
    "ekf3.c:ekf3_update_step": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    "ukf3.c:ukf3_predict_point": ["gf_ekf3_motion_forward_turn"],
    "ukf3.c:ukf3_point_image": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    "pf3.c:pf3_propagate": ["gf_ekf3_motion_forward_turn"],
    "pf3.c:pf3_mahalanobis": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
}
# Any other function with an indirect call (gf_ekf's steps: it has no
# built-in models): counted as the deepest of EKF3's built-in models, and
# named in the report's notes.
ALL_MODELS = ["gf_ekf3_motion_forward_turn", "gf_ekf3_meas_x",
              "gf_ekf3_meas_xy"]
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


def archive_members(prefix, build):
    """{"kf2.c": the local function symbols of kf2.c.obj, ...} for the
    objects of the core's archive (objects a build tree still holds from
    sources since removed are not in it, and are ignored)."""
    lib = core_archive(build)
    members = {m[:-len(".obj")]: set() for m in
               run([prefix + "ar", "t", lib]).split() if m.endswith(".c.obj")}
    for line in run([prefix + "nm", "-A", lib]).splitlines():
        m = re.match(r"^.*:([\w.+-]+\.c)\.obj:\s*[0-9a-f]*\s+t\s+(\S+)$", line)
        if m and m.group(1) in members:
            members[m.group(1)].add(m.group(2))
    return members


def qualify(members, stem, name):
    """A static function's name, made unique by its object ("kf2.c:update"):
    two translation units may each have their own (static inline helpers of
    a shared header, compiled into both)."""
    return f"{stem}:{name}" if name in members.get(stem, ()) else name


def modules(prefix, build):
    names = [m[:-len(".c")] for m in archive_members(prefix, build)]
    return sorted(names, key=lambda n: (MODULE_ORDER.index(n)
                                        if n in MODULE_ORDER else 99, n))


def module_sizes(prefix, build):
    """{module: {text, rodata, data, bss}} from the objects' sections."""
    sizes = {}
    for mod in modules(prefix, build):
        obj = os.path.join(build, "gaussfilt/CMakeFiles/gaussfilt.dir/src",
                           mod + ".c.obj")
        acc = {"text": 0, "rodata": 0, "data": 0, "bss": 0}
        for line in run([prefix + "size", "-A", obj]).splitlines():
            parts = line.split()
            if len(parts) >= 2 and parts[1].isdigit():
                kind = section_kind(parts[0])
                if kind:
                    acc[kind] += int(parts[1])
        sizes[mod] = acc
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

def read_su(build, members):
    frames = {}
    for su in glob.glob(os.path.join(
            build, "gaussfilt/CMakeFiles/gaussfilt.dir/src/*.su")):
        stem = os.path.basename(su)[:-len(".su")]
        if stem not in members:
            continue
        for line in open(su):
            loc, size, kind = line.rstrip("\n").split("\t")
            name = loc.rsplit(":", 1)[-1]
            # gcc's .su says "f.constprop.isra" where the symbol is
            # "f.constprop.0.isra.0".
            name = re.sub(r"\.(isra|part|constprop|cold)(?=\.|$)", r".\1.0",
                          name)
            if kind != "static":
                sys.exit(f"{su}: {name} has a {kind} frame")
            frames[qualify(members, stem, name)] = int(size)
    return frames


def read_ci(build, members):
    """Edges of gcc's call graph; a static function's file prefix becomes
    its object's (qualify)."""
    edges = {}
    for ci in glob.glob(os.path.join(
            build, "gaussfilt/CMakeFiles/gaussfilt.dir/src/*.ci")):
        stem = os.path.basename(ci)[:-len(".ci")]
        if stem not in members:
            continue
        for m in re.finditer(r'edge: \{ sourcename: "([^"]+)" '
                             r'targetname: "([^"]+)"', open(ci).read()):
            src = qualify(members, stem, m.group(1).rsplit(":", 1)[-1])
            dst = qualify(members, stem, m.group(2).rsplit(":", 1)[-1])
            edges.setdefault(src, set()).add(dst)
    return edges


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


# picolibc's -Os code saves registers through libgcc's millicode: on rv32,
# __riscv_save_N moves sp by 16 bytes per group of four registers.
RISCV_SAVE = re.compile(r"^__riscv_(save|restore)_(\d+)$")


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


def disassemble(prefix, archive, arm, members=None):
    """{function: (frame, callees, has_indirect)} for an archive: frame
    from the prologue, callees every function it calls or jumps to
    (relocations, and the direct bl/jal the assembler resolved itself).
    members: the core's (archive_members), whose static functions are
    qualified."""
    out = run([prefix + "objdump", "-dr", "--no-show-raw-insn", archive])
    members = members or {}
    stem = None
    q = lambda n: qualify(members, stem, n)  # noqa: E731
    funcs, aliases = {}, {}
    name, insns, callees, indirect = None, [], set(), False

    def flush():
        if name:
            old = funcs.get(name)
            new = (prologue_frame(insns, arm), callees - {name}, indirect)
            if old is None or new[0] > old[0]:
                funcs[name] = new

    section_fn = None
    for line in out.splitlines():
        m = re.match(r"^([\w.+-]+\.c)\.obj:\s+file format", line)
        if m:
            flush()
            name = None
            stem = m.group(1)
            continue
        m = re.match(r"^Disassembly of section \.text\.([\w$]+):$", line)
        if m:
            section_fn = m.group(1)
            continue
        m = re.match(r"^[0-9a-f]+ <([\w.$]+)>:$", line)
        if m and not m.group(1).startswith(".L"):
            flush()
            name, insns, callees, indirect = q(m.group(1)), [], set(), False
            # picolibc labels cosf's code _cosf; its section says cosf.
            if section_fn and q(section_fn) != name:
                aliases[name] = section_fn
            section_fn = None
            continue
        if m or name is None:
            continue
        m = CALL_RELOCS.search(line)
        if m:
            if not m.group(2).startswith(".L"):
                callees.add(q(m.group(2)))
            continue
        m = re.match(r"^\s+([0-9a-f]+):\s+(.*)$", line)
        if not m or m.group(2).startswith("R_"):
            continue  # not an instruction (other relocations: RELAX, ...)
        text = m.group(2).split(";")[0].split("#")[0].strip() \
            if not arm else m.group(2).split("@")[0].split(";")[0].strip()
        insns.append(text)
        parts = text.split(None, 1)
        op = parts[0] if parts else ""
        args = parts[1] if len(parts) > 1 else ""
        if arm:
            if op == "blx" and re.match(r"^(r\d+|ip|lr|sl|fp)$", args):
                indirect = True
            bm = re.match(r"^[0-9a-f]+ <([\w.$]+)>$", args)
            if op in ("bl", "blx", "b", "b.w", "b.n") and bm and \
                    not bm.group(1).startswith(".L"):
                callees.add(q(bm.group(1)))
        else:
            if op in ("jalr", "c.jalr") and not args.startswith("ra"):
                indirect = True
            bm = re.match(r"^(ra,)?[0-9a-f]+ <([\w.$]+)>$", args)
            if op in ("jal", "j") and bm and \
                    not bm.group(2).startswith(".L"):
                callees.add(q(bm.group(2)))
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


# sinf/cosf reach __kernel_rem_pio2f (a 0x100+ byte frame) only for
# |x| >= 2^7 pi/2; the core calls them on a heading wrapped to (-pi, pi].
UNREACHABLE = {"__kernel_rem_pio2f"}


def stack_report(prefix, build, exclude=frozenset()):
    """({public function: (frame, depth, chain)}, notes): depth through the
    deepest chain of calls and jumps, each on top of its caller's frame."""
    arm = prefix.startswith("arm")
    members = archive_members(prefix, build)
    su = read_su(build, members)
    ci = read_ci(build, members)
    core = disassemble(prefix, core_archive(build), arm, members)
    ext = {}
    for lib in libraries(build):
        for k, v in disassemble(prefix, lib, arm).items():
            ext.setdefault(k, v)
    mismatches = [f"{n}: .su {su[n]}, prologue {core[n][0]}"
                  for n in su if n in core and core[n][0] != su[n]]

    unknown, guessed = set(), set()
    # Link names carry the precision (include/gaussfilt/names.h):
    # gf_ekf3_update_f32. CALLBACKS and ALL_MODELS use the plain names.
    sfx = next((m.group(0) for n in su
                for m in [re.search(r"_f(32|64)$", n)] if m and
                n.startswith("gf_")), "")

    def plain(n):
        return n[:-len(sfx)] if sfx and n.startswith("gf_") and \
            n.endswith(sfx) else n

    def linked(names):
        return {x + sfx if x.startswith("gf_") else x for x in names}

    def save_area(n):
        """Bytes a library function's registers take through libgcc's
        millicode (rv32 -msave-restore: `jal t0, __riscv_save_N` before the
        prologue's own sp adjustment): they stay on the stack during every
        call the function makes, so they belong to its frame."""
        total = 0
        for c in (ext[n][1] if n in ext and n not in su else ()):
            m = RISCV_SAVE.match(c)
            if m and m.group(1) == "save":
                total = max(total, 16 * (int(m.group(2)) // 4 + 1))
        return total

    def frame(n):
        if n in su:
            return su[n]
        if RISCV_SAVE.match(n):
            return 0  # counted in its caller's frame (save_area)
        if n in ext:
            return ext[n][0] + save_area(n)
        unknown.add(n)
        return 0

    none = (0, set(), False)

    def callees(n):
        c = set()
        if n in su:
            c |= ci.get(n, set())
            c |= core.get(n, none)[1]
        elif n in ext:
            c |= ext[n][1]
        if "__indirect_call" in c or core.get(n, none)[2]:
            if plain(n) not in CALLBACKS:
                guessed.add(plain(n))
            c |= linked(CALLBACKS.get(plain(n), ALL_MODELS))
        c.discard("__indirect_call")
        c = {x for x in c if not RISCV_SAVE.match(x)}  # in frame(n)
        c.discard(n)
        return {x.replace("__builtin_", "") for x in c}

    memo = {}

    def depth(n, path=()):
        """(depth, deepest callee): frame(n) plus the deepest of what n
        calls or jumps to."""
        if n in path:
            sys.exit("recursion: " + " -> ".join(path + (n,)))
        if n not in memo:
            best, via = frame(n), None
            for c in sorted(callees(n) - exclude):
                d = frame(n) + depth(c, path + (n,))[0]
                if d > best:
                    best, via = d, c
            memo[n] = (best, via)
        return memo[n]

    public = sorted(n for n in su if n.startswith("gf_"))
    rows = {}
    for n in public:
        d, via = depth(n)
        chain = plain(n)
        while via:
            chain += " → " + plain(via)
            _, via = memo[via]
        rows[plain(n)] = (su[n], d, chain)
    return rows, mismatches, unknown, guessed


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
    lines = []
    today = datetime.date.today().isoformat()
    versions = []
    for pfx in ("arm-none-eabi-", "riscv64-unknown-elf-"):
        v = run([pfx + "gcc", "--version"]).splitlines()[0]
        versions.append(f"`{v}`")
    lines.append(f"Generated by `scripts/footprint --docs` on {today} with "
                 + " and ".join(versions)
                 + "; `-Os`, float build (`gf_real` = float), "
                 "`-ffunction-sections -fdata-sections`, `--gc-sections`.")
    lines.append("")

    results = {}
    for key, label, pfx in TARGETS:
        build = os.path.join(build_root, f"fw-{key}-float")
        results[key] = {
            "label": label,
            "mods": module_sizes(pfx, build),
            "structs": struct_sizes(pfx, build),
            "stack": stack_report(pfx, build),
            "stack_reach": stack_report(pfx, build, UNREACHABLE),
            "images": {img: image_sizes(pfx, os.path.join(
                build, f"gf_fw_{img}.elf")) for img, _ in
                [("base", "")] + IMAGES},
            "bd": {img: map_breakdown(os.path.join(
                build, f"gf_fw_{img}.map")) for img, _ in
                [("base", "")] + IMAGES},
            "syms": run([pfx + "nm", os.path.join(build,
                                                  "gf_fw_kf2_ekf3.elf")]),
        }
    m4 = results["cortex-m4f"]
    met = lambda ok: "**met**" if ok else "**NOT met**"  # noqa: E731

    def delta(key, img):
        ims = results[key]["images"]
        return flash(ims[img]) - flash(ims["base"])

    # Flash per image and target.
    lines += ["Flash each minimal image adds to the base image "
              "(`firmware/min_image.c`: init, predict, update and the cov "
              "accessor of its filters, inputs and outputs volatile; the base "
              "image has the same start-up and I/O and no filter), text + "
              "data, C library, libm and libgcc included:", "",
              "| image | " + " | ".join(results[k]["label"]
                                        for k, _, _ in TARGETS) + " |",
              "|---|" + "---|" * len(TARGETS)]
    for img, label in IMAGES:
        cells = []
        for key, _, _ in TARGETS:
            d = delta(key, img)
            lim = FLASH_TARGETS.get((img, key))
            cell = f"{fmt_b(d)} ({kib(d)})"
            if lim is not None:
                cell += f"; target {kib(lim)}: {met(d <= lim)}"
            cells.append(cell)
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append(f"| base image (absolute) | " + " | ".join(
        fmt_b(flash(results[k]["images"]["base"])) for k, _, _ in TARGETS)
        + " |")
    lines.append("")

    lines += ["What the delta is made of, Cortex-M4F (bytes, from the link "
              "map; per function: [where the flash goes](#where-the-flash-goes)):", "",
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
    lines += ["Stack: the deepest public function of every module (EKF3's "
              "callbacks counted as the deepest built-in model), counted "
              "with every jump as a call:", "",
              "| target | limit | deepest public function | depth | | "
              "functions over the limit |",
              "|---|---|---|---|---|---|"]
    for key, label, _ in TARGETS:
        rows = results[key]["stack"][0]
        lim = STACK_TARGETS[key]
        d, n = max((d, n) for n, (_, d, _) in rows.items())
        over = sorted(n for n, (_, dd, _) in rows.items() if dd > lim)
        lines.append(f"| {label} | {lim} B | `{n}` | {d} B | {met(d <= lim)}"
                     f" | " + (", ".join(f"`{o}` ({rows[o][1]})" for o in over)
                               if over else "none") + " |")
    lines.append("")
    reach = []
    for key, label, _ in TARGETS:
        full = results[key]["stack"][0]
        part = results[key]["stack_reach"][0]
        lim = STACK_TARGETS[key]
        changed = sorted(n for n in full if part[n][1] != full[n][1])
        if changed:
            d, n = max((d, n) for n, (_, d, _) in part.items())
            over = sorted(x for x, (_, dd, _) in part.items() if dd > lim)
            reach.append(f"{label}: deepest `{n}` {d} B ({met(d <= lim)}), "
                         f"over the limit: "
                         + (", ".join(f"`{o}`" for o in over) if over
                            else "none"))
    if reach:
        lines += ["The same without the large-argument path of the C "
                  "library's sinf/cosf (`__kernel_rem_pio2f`, unreachable "
                  "from the core: it wraps the heading to (-pi, pi] before "
                  "it calls them): " + "; ".join(reach) + ".", ""]

    lines += ["Worst-case stack depth of every public function (bytes: own "
              "frame from `-fstack-usage`; depth = frame + the deepest of "
              "what the function calls or jumps to, libm, libc and libgcc "
              "included, a jump counted like a call, its frame on top of the "
              "caller's; **!**: over the target's limit). A user model adds "
              "max(0, its own depth - the built-in's) to EKF3's steps.", "",
              "| function | " + " | ".join(
                  f"{results[k]['label']} frame / depth" for k, _, _ in TARGETS)
              + " | deepest chain (Cortex-M4F) |",
              "|---|" + "---|" * len(TARGETS) + "---|"]
    for n in sorted(m4["stack"][0]):
        cells = []
        for key, _, _ in TARGETS:
            f, d, _ = results[key]["stack"][0][n]
            flag = " **!**" if d > STACK_TARGETS[key] else ""
            cells.append(f"{f} / {d}{flag}")
        chain = m4["stack"][0][n][2]
        lines.append(f"| `{n}` | " + " | ".join(cells) + f" | {chain} |")
    lines.append("")
    notes = []
    for key, label, _ in TARGETS:
        _, mism, unknown, guessed = results[key]["stack"]
        if mism:
            notes.append(f"{label}: prologue and .su disagree: "
                         + "; ".join(mism) + ".")
        if unknown:
            notes.append(f"{label}: no frame found for "
                         + ", ".join(sorted(unknown)) + " (counted as 0).")
        if guessed:
            notes.append(f"{label}: the indirect calls of "
                         + ", ".join(f"`{g}`" for g in sorted(guessed))
                         + " counted as the deepest built-in model.")
    if not any(results[k]["stack"][1] or results[k]["stack"][2]
               for k, _, _ in TARGETS):
        notes.insert(0, "Cross-check: for every core function the frame read "
                     "from the disassembly's prologue equals gcc's `.su` "
                     "figure, on all three targets; every callee has a known "
                     "frame.")
    lines += ["Stack analysis notes: " + " ".join(notes), ""]

    # Modules.
    lines += ["Library objects, per module (bytes; `.data` and `.bss` must "
              "stay 0: the core has no globals):", "",
              "| module | " + " | ".join(
                  f"{results[k]['label']} .text / .rodata / .data / .bss"
                  for k, _, _ in TARGETS) + " |",
              "|---|" + "---|" * len(TARGETS)]
    for mod in list(m4["mods"]) + ["total"]:
        cells = []
        for key, _, _ in TARGETS:
            mods = results[key]["mods"]
            if mod == "total":
                s = {k: sum(m[k] for m in mods.values())
                     for k in ("text", "rodata", "data", "bss")}
            else:
                s = mods.get(mod, {"text": 0, "rodata": 0, "data": 0,
                                   "bss": 0})
            cells.append(f"{s['text']} / {s['rodata']} / {s['data']} / "
                         f"{s['bss']}")
        name = f"`{mod}.c`" if mod != "total" else "**total**"
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines.append("")

    # Structs.
    lines += ["`sizeof` of the public structs (bytes, float build; the double "
              "build doubles every `gf_real`):", "",
              "| struct | " + " | ".join(results[k]["label"]
                                         for k, _, _ in TARGETS) + " |",
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
