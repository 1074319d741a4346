#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The firmware footprint report, from the build trees scripts/footprint
made: per module and target .text/.rodata/.data/.bss, sizeof of the public
structs, worst-case stack depth of every public function, and the minimal
image's cost, in the float build at -Os (fw-TARGET-float), with the
targets stated met or not; beside it the cost of the same image with the
hand-written checked sound floor of bench/ref.c in the filters' place
(gf_fw_floor), held against the same targets. Prints a Markdown fragment; --docs FILE splices
it into FILE between its footprint markers.

Stack depth: a function's own frame is gcc's -fstack-usage figure (.su) for
the core and, for what the core calls in libm, libc and libgcc (which Debian
builds without -fstack-usage), the frame read from the prologue of its
disassembly (push/vpush/sub sp on Arm, addi sp on RISC-V). Edges come from
gcc's -fcallgraph-info (.ci) plus the call relocations of the disassembly,
so libgcc's soft-float helpers (invisible to .ci) are counted. The only
indirect calls are EKF3's model callbacks; they are counted as the deepest
built-in model (see CALLBACKS) and the caller's frame at the call is
reported so that a user callback's own depth can be added.

Tail calls: a function that ends in a jump to another has released its
own frame when the callee runs, so depth(f) = max(frame(f) + the deepest of
its ordinary calls, the deepest of its tail calls). The jumps: on Arm a
`b.w`/`b` with an R_ARM_THM_JUMP24/R_ARM_JUMP24 relocation (Cortex-M0+'s
Thumb-1 has none: gcc calls there); on RISC-V `auipc tN` with
R_RISCV_CALL(_PLT) followed by `jr tN` (gcc's `tail`), or `j` with
R_RISCV_JAL. A jump counts as a tail call only when the disassembly shows
it: the straight-line code right before it (back to the previous branch or
branch target) gives back exactly the function's whole frame (Arm:
pop/ldmia without pc, add sp, vpop; RISC-V: addi sp), so sp is the
caller's again at the jump. Any other jump is counted like a call: its
frame on top of the caller's whole frame (conservative).
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
# The modules: every src/*.c the build compiled, in this order first.
MODULE_ORDER = ["ldl", "mat", "cov2", "kf2", "ekf3", "status", "rng", "if2", "ukf3",
                "pf3"]
STRUCTS = ["gf_kf2", "gf_ekf3", "gf_kf2_model", "gf_kf2_meas",
           "gf_ekf3_motion", "gf_ekf3_meas", "gf_innovation", "gf_ellipse",
           "gf_vec2", "gf_vec3", "gf_mat2", "gf_mat3",
           "gf_if2", "gf_ukf3", "gf_ukf3_params", "gf_pf3", "gf_pf3_particle",
           "gf_rng"]
# Indirect calls: which functions a callback slot runs when the built-in
# models are used.
CALLBACKS = {
    # EKF3's entry points call the motion model themselves; the update's
    # measurement model is called from its step.
    "gf_ekf3_predict": ["gf_ekf3_motion_forward_turn"],
    "gf_ekf3_predict_prepared": ["gf_ekf3_motion_forward_turn"],
    "gf_ekf3_update": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    "ekf3.c:ekf3_update_step": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    # UKF3 and PF3 take EKF3's callbacks (PF3's from static helpers;
    # UKF3's predict from predict_point, a call of its own, its update
    # from point_image, a call of its own under -Os, inlined into
    # update_points elsewhere).
    "gf_ukf3_predict": ["gf_ekf3_motion_forward_turn"],
    "ukf3.c:predict_point": ["gf_ekf3_motion_forward_turn"],
    "gf_ukf3_update": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    "ukf3.c:point_image": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    "ukf3.c:update_points": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    # PF3's predict calls g from propagate (not inlined under -Os), or
    # itself where propagate is inlined (other optimisation levels). Static
    # functions are named with their object (qualify).
    "gf_pf3_predict": ["gf_ekf3_motion_forward_turn"],
    "pf3.c:propagate": ["gf_ekf3_motion_forward_turn"],
    "gf_pf3_update": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
    "pf3.c:mahalanobis": ["gf_ekf3_meas_x", "gf_ekf3_meas_xy"],
}
# Any other function with an indirect call: counted as the deepest of all
# the built-in models (and named in the report's notes).
ALL_MODELS = ["gf_ekf3_motion_forward_turn", "gf_ekf3_meas_x",
              "gf_ekf3_meas_xy"]
STACK_LIMIT = 256
IMAGE_LIMIT = 6 * 1024
CORE_LIMIT = 3 * 1024
BELIEF_LIMITS = {"gf_kf2": 24, "gf_ekf3": 48}
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


CALL_RELOCS = re.compile(r"R_(ARM_THM_CALL|ARM_CALL|ARM_THM_JUMP24|"
                         r"ARM_JUMP24|RISCV_CALL|RISCV_CALL_PLT|RISCV_JAL)\s+"
                         r"([\w.$]+)")
ARM_JUMP_RELOCS = ("ARM_THM_JUMP24", "ARM_JUMP24")
# Arm instructions that end a straight-line run of code: branches, returns
# (pop/ldmia with pc), IT blocks (conditional instructions follow).
ARM_FLOW = re.compile(r"^(b|bl|blx|bx|cbz|cbnz|tbb|tbh|it\w*)(\.[nw])?$|"
                      r"^b(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le)"
                      r"(\.[nw])?$")
ARM_TARGET = re.compile(r"^(?:\w+, )*([0-9a-f]+) <[\w.$]+\+0x[0-9a-f]+>$")
RISCV_FLOW = re.compile(r"^(c\.)?(b\w*|j|jal|jalr|jr|ret|tail|call|ebreak|"
                        r"ecall|mret)$")
RISCV_TARGET = re.compile(r"^(?:[\w.]+,)*([0-9a-f]+) <[\w.$+]+>$")


def arm_release(text):
    """Bytes an Arm instruction gives back to the stack (pop/ldmia sp!
    without pc, add sp, vpop); None if it returns or moves sp down."""
    parts = text.split(None, 1)
    op, args = parts[0], parts[1] if len(parts) > 1 else ""
    lst = ARM_REG_LIST.search(args)
    if op in ("pop", "pop.w") or (op in ("ldmia", "ldmia.w") and
                                   args.startswith("sp!")):
        return None if "pc" in lst.group(1) else count_regs(lst.group(1), 4)
    if op in ("vpop", "vldmia") and lst and (op == "vpop" or
                                             args.startswith("sp!")):
        regs = lst.group(1)
        return count_regs(regs, 8 if "d" in regs else 4)
    m = re.match(r"^sp, (sp, )?#(\d+)$", args)
    if m and op in ("add", "add.w", "addw"):
        return int(m.group(2))
    if op in ("push", "push.w", "vpush", "stmdb", "vstmdb", "sub", "sub.w",
              "subw") and args.startswith("sp"):
        return None
    return 0


def riscv_release(text):
    """Bytes a RISC-V instruction gives back to the stack (addi sp,sp,N);
    None if it moves sp down."""
    parts = text.split(None, 1)
    m = re.match(r"^sp,sp,(-?\d+)$", parts[1] if len(parts) > 1 else "")
    if m and parts[0] in ("addi", "add", "c.addi", "c.addi16sp"):
        n = int(m.group(1))
        return n if n >= 0 else None
    return 0


def branch_targets(insns, arm, labels):
    """The addresses a function's code branches to (insns: (address, text);
    labels: addresses of its local labels), or None if it has a computed
    branch (targets unknown: none of its jumps is judged a tail call)."""
    flow, target_re = (ARM_FLOW, ARM_TARGET) if arm else \
        (RISCV_FLOW, RISCV_TARGET)
    targets = set(labels)
    for _, text in insns:
        parts = text.split(None, 1)
        if not parts:
            continue
        if arm and (parts[0] in ("tbb", "tbh") or (len(parts) > 1 and
                                                  parts[1].startswith("pc"))):
            return None
        m = target_re.match(parts[1]) if len(parts) > 1 else None
        if m and flow.match(parts[0]):
            targets.add(int(m.group(1), 16))
    return targets


def tail_call(insns, i, frame, arm, targets):
    """True if the jump at insns[i] (address, text) runs after the
    function's whole frame is released: the straight-line code before it
    (back to a branch, or to a branch target, included) gives back exactly
    `frame` bytes. targets: branch_targets() of the function, not None."""
    flow = ARM_FLOW if arm else RISCV_FLOW
    released = 0
    for addr, text in reversed(insns[:i]):
        op = text.split(None, 1)[0] if text else ""
        if flow.match(op):
            break
        r = arm_release(text) if arm else riscv_release(text)
        if r is None:
            return False
        released += r
        if addr in targets:
            break
    return released == frame


def disassemble(prefix, archive, arm, members=None):
    """{function: (frame, callees, has_indirect, tail_callees)} for an
    archive: tail_callees are the targets of the tail calls tail_call
    accepts; any other call or jump is in callees. members: the core's
    (archive_members), whose static functions are qualified."""
    out = run([prefix + "objdump", "-dr", "--no-show-raw-insn", archive])
    members = members or {}
    stem = None
    q = lambda n: qualify(members, stem, n)  # noqa: E731
    funcs, aliases = {}, {}
    name, insns, callees, indirect = None, [], set(), False
    addrs, jumps, labels = [], [], set()

    def flush():
        if name:
            old = funcs.get(name)
            frame = prologue_frame(insns, arm)
            tails = set()
            code = list(zip(addrs, insns))
            targets = branch_targets(code, arm, labels) if jumps else None
            for i, target in jumps:
                # RISC-V's auipc tN must be followed by jr tN.
                ok = arm or insns[i].split()[0] == "j" or (
                    i + 1 < len(insns) and insns[i + 1].split() ==
                    ["jr", insns[i].split(None, 1)[1].split(",")[0]])
                if ok and targets is not None and \
                        tail_call(code, i, frame, arm, targets):
                    tails.add(target)
                else:
                    callees.add(target)
            new = (frame, callees, indirect, tails - callees)
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
        m = re.match(r"^([0-9a-f]+) <([\w.$]+)>:$", line)
        if m and m.group(2).startswith(".L"):
            labels.add(int(m.group(1), 16))  # RISC-V keeps its local labels
        m = re.match(r"^[0-9a-f]+ <([\w.$]+)>:$", line)
        if m and not m.group(1).startswith(".L"):
            flush()
            name, insns, callees, indirect = q(m.group(1)), [], set(), False
            addrs, jumps, labels = [], [], set()
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
                # The relocation follows its instruction: a jump (b/b.w) is
                # a tail call candidate, judged at flush().
                parts = insns[-1].split(None, 1) if insns else [""]
                op = parts[0]
                rd = parts[1].split(",")[0] if len(parts) > 1 else ""
                if (arm and m.group(1) in ARM_JUMP_RELOCS and
                        op in ("b", "b.w")) or \
                        (not arm and m.group(1).startswith("RISCV_CALL") and
                         op == "auipc" and rd != "ra") or \
                        (not arm and m.group(1) == "RISCV_JAL" and op == "j"):
                    jumps.append((len(insns) - 1, q(m.group(2))))
                else:
                    callees.add(q(m.group(2)))
            continue
        m = re.match(r"^\s+([0-9a-f]+):\s+(.*)$", line)
        if not m or m.group(2).startswith("R_"):
            continue  # not an instruction (other relocations: RELAX, ...)
        text = m.group(2).split(";")[0].split("#")[0].strip() \
            if not arm else m.group(2).split("@")[0].split(";")[0].strip()
        insns.append(text)
        addrs.append(int(m.group(1), 16))
        parts = text.split(None, 1)
        op = parts[0] if parts else ""
        args = parts[1] if len(parts) > 1 else ""
        if arm:
            if op == "blx" and re.match(r"^(r\d+|ip|lr|sl|fp)$", args):
                indirect = True
            bm = re.match(r"^[0-9a-f]+ <([\w.$]+)>$", args)
            if op in ("bl", "blx") and bm and q(bm.group(1)) != name:
                callees.add(q(bm.group(1)))
        else:
            if op in ("jalr", "c.jalr") and not args.startswith("ra"):
                indirect = True
            bm = re.match(r"^(ra,)?[0-9a-f]+ <([\w.$]+)>$", args)
            if op == "jal" and bm and q(bm.group(2)) != name:
                callees.add(q(bm.group(2)))
    flush()
    for a, n in aliases.items():
        funcs.setdefault(n, funcs[a])
    return funcs


def libraries(build):
    """The C library, libm and libgcc archives the minimal image linked."""
    libs = []
    for line in open(os.path.join(build, "gf_fw_min.map")):
        m = re.match(r"^LOAD (\S+/lib(c|m|gcc|c_nano|m_nano)\.a)$", line)
        if m and m.group(1) not in libs:
            libs.append(os.path.normpath(m.group(1)))
    return libs


# sinf/cosf reach __kernel_rem_pio2f (a 0x100+ byte frame) only for
# |x| >= 2^7 pi/2; the core calls them on a heading wrapped to (-pi, pi].
UNREACHABLE = {"__kernel_rem_pio2f"}


def stack_report(prefix, build, exclude=frozenset()):
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

    none = (0, set(), False, set())

    def tails(n):
        """Verified tail calls only (disassemble); .ci lists them as edges
        too, so callees() leaves them out."""
        return (core.get(n, none) if n in su else ext.get(n, none))[3]

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
        c -= tails(n)
        c.discard(n)
        return {x.replace("__builtin_", "") for x in c}

    memo = {}

    def depth(n, path=()):
        """(depth, deepest callee, 1 if that is a tail call): frame(n) plus
        the deepest ordinary call, or the deepest tail call if deeper (n's
        frame is gone by then)."""
        if n in path:
            sys.exit("recursion: " + " -> ".join(path + (n,)))
        if n not in memo:
            best, via, tail = frame(n), None, 0
            for c in sorted(callees(n) - exclude):
                d = frame(n) + depth(c, path + (n,))[0]
                if d > best:
                    best, via = d, c
            for c in sorted(tails(n) - exclude):
                d = depth(c, path + (n,))[0]
                if d > best:
                    best, via, tail = d, c, 1
            memo[n] = (best, via, tail)
        return memo[n]

    public = sorted(n for n in su if n.startswith("gf_"))
    rows = {}
    for n in public:
        d, via, tail = depth(n)
        chain = plain(n)
        while via:
            chain += (" ⇢ " if tail else " → ") + plain(via)
            _, via, tail = memo[via]
        rows[plain(n)] = (su[n], d, chain)
    return rows, mismatches, unknown, guessed


# ---- images -----------------------------------------------------------------

def image_sizes(prefix, elf):
    text, data, bss = run([prefix + "size", elf]).splitlines()[1].split()[:3]
    return int(text), int(data), int(bss)


NOT_LOADED = (".debug", ".comment", ".ARM.attributes", ".riscv.attributes",
              ".stab", ".note", ".gnu")


def map_breakdown(mapfile):
    """Bytes per origin (core, libm, libc, libgcc, app) in the final image."""
    acc = {}
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
        size, origin = int(m.group(3), 16), m.group(4)
        if not sect or size == 0 or out_sect.startswith(NOT_LOADED):
            continue
        if "libgaussfilt.a" in origin:
            key = "gaussfilt"
        elif "gf_fw_ref.dir" in origin:
            key = "floor"  # bench/ref.c, in gf_fw_floor only
        elif re.search(r"/libm(_nano)?\.a\(", origin):
            key = "libm"
        elif re.search(r"/libgcc\.a\(", origin):
            key = "libgcc"
        elif re.search(r"/libc(_nano)?\.a\(", origin):
            # picolibc keeps libm inside libc.a
            key = "libm" if "libm_" in origin else "libc"
        else:
            key = "app"
        acc[key] = acc.get(key, 0) + size
    return acc


def fmt_delta(b):
    return f"{b} B ({b / 1024:.2f} KiB)"


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
            "base": image_sizes(pfx, os.path.join(build, "gf_fw_base.elf")),
            "min": image_sizes(pfx, os.path.join(build, "gf_fw_min.elf")),
            "breakdown": map_breakdown(os.path.join(build, "gf_fw_min.map")),
            "basebd": map_breakdown(os.path.join(build, "gf_fw_base.map")),
            "syms": run([pfx + "nm", os.path.join(build, "gf_fw_min.elf")]),
            "floor": image_sizes(pfx, os.path.join(build, "gf_fw_floor.elf")),
            "floorbd": map_breakdown(os.path.join(build, "gf_fw_floor.map")),
        }

    # Targets.
    m4 = results["cortex-m4f"]
    flash = lambda s: s[0] + s[1]  # noqa: E731  text (+rodata) + data copy
    d_flash = flash(m4["min"]) - flash(m4["base"])
    dbl = sorted({ln.split()[-1] for ln in m4["syms"].splitlines()
                  if DOUBLE_SYMS.match(ln.split()[-1])})
    kf2 = m4["structs"]["gf_kf2"]
    ekf3 = m4["structs"]["gf_ekf3"]
    # The stack budget holds for every public function of every module
    # (KF2, EKF3, their helpers, and IF2, UKF3, PF3, the generator).
    worst = max((d, n) for n, (_, d, _) in m4["stack"][0].items())
    reach = max((d, n) for n, (_, d, _) in m4["stack_reach"][0].items())
    met = lambda ok: "**met**" if ok else "**NOT met**"  # noqa: E731
    # The hand-written checked sound floor in the filters' place
    # (gf_fw_floor): its flash over the base image, and its own code (what
    # the library's core code is to the library's image: bench/ref.c's
    # functions and the library's built-in models and angle helpers it
    # calls; main's calls and the C library excluded).
    f_flash = flash(m4["floor"]) - flash(m4["base"])
    fbd, bbd = m4["floorbd"], m4["basebd"]
    f_own = fbd.get("floor", 0) + fbd.get("gaussfilt", 0) - \
        bbd.get("gaussfilt", 0)
    l_own = m4["breakdown"].get("gaussfilt", 0) - bbd.get("gaussfilt", 0)
    side = lambda ok: "within" if ok else "above"  # noqa: E731
    lines += [
        "| target (Cortex-M4F, float, `-Os`) | limit | measured | |",
        "|---|---|---|---|",
        f"| KF2 + EKF3 image minus the same image without them (flash, "
        f"libm included) | 6 KiB | {fmt_delta(d_flash)} | "
        f"{met(d_flash <= IMAGE_LIMIT)} |",
        f"| the same with the hand-written checked sound floor in the "
        f"filters' place (`bench/ref.c`, below) | 6 KiB | "
        f"{fmt_delta(f_flash)} | the floor is "
        f"{side(f_flash <= IMAGE_LIMIT)} it |",
        f"| the core's own code in that image (the library's: its objects; "
        f"the floor's: `bench/ref.c`'s functions and the built-in models it "
        f"calls) | 3 KiB | library {fmt_delta(l_own)}, floor "
        f"{fmt_delta(f_own)} | {met(l_own <= CORE_LIMIT)}; the floor is "
        f"{side(f_own <= CORE_LIMIT)} it |",
        f"| one KF2 belief (`sizeof(gf_kf2)`) | 24 B | {kf2} B | "
        f"{met(kf2 <= BELIEF_LIMITS['gf_kf2'])} |",
        f"| one EKF3 belief (`sizeof(gf_ekf3)`) | 48 B | {ekf3} B | "
        f"{met(ekf3 <= BELIEF_LIMITS['gf_ekf3'])} |",
        f"| deepest public function, every module (built-in models) | 256 B "
        f"| {worst[0]} B (`{worst[1]}`) | {met(worst[0] <= STACK_LIMIT)} |",
        f"| the same, without newlib's large-argument path of sinf/cosf "
        f"(`__kernel_rem_pio2f`, unreachable: the heading is wrapped to "
        f"(-pi, pi]) | 256 B | {reach[0]} B (`{reach[1]}`) | "
        f"{met(reach[0] <= STACK_LIMIT)} |",
        "",
        f"Double promoted in the float image: "
        + (", ".join(f"`{s}`" for s in dbl) if dbl else "none (no double "
           "libm function, no soft-double helper)") + ".",
        "",
    ]

    # Minimal images.
    lines += ["Minimal images (`firmware/min_image.c`: one KF2 predict/update, "
              "one EKF3 predict/update with the built-in models; the base "
              "image has the same start-up and I/O, no filter), `-Os`. "
              "Bytes:", "",
              "| target | base flash | KF2+EKF3 flash | delta flash | delta RAM "
              "| delta: core | libm | libc | libgcc |",
              "|---|---|---|---|---|---|---|---|---|"]
    for key, _, _ in TARGETS:
        r = results[key]
        df = flash(r["min"]) - flash(r["base"])
        dr = (r["min"][1] + r["min"][2]) - (r["base"][1] + r["base"][2])
        bd, bb = r["breakdown"], r["basebd"]
        part = lambda k: bd.get(k, 0) - bb.get(k, 0)  # noqa: E731
        lines.append(f"| {r['label']} | {flash(r['base'])} | {flash(r['min'])} "
                     f"| {df} | {dr} | {part('gaussfilt')} | {part('libm')} "
                     f"| {part('libc')} | {part('libgcc')} |")
    lines.append("")

    # The floor's image.
    lines += ["The checked sound floor's image (`firmware/min_image.c` with "
              "`GF_FW_FLOOR`: the same calls, init, predict, update and cov "
              "of KF2 and EKF3 with the built-in models, made to "
              "`bench/ref.c`'s hand-written U D U^T steps with the checks the "
              "plain API promises: the priors, R and Q judged and factored in "
              "closed form, updates of m = 1 to 3 measured quantities "
              "whitened by Q's factors, as the library's; and the "
              "library's order of the factors and precision of the prior), "
              "`-Os`, against the same base. Bytes:", "",
              "| target | floor flash | delta flash | delta RAM "
              "| delta: bench/ref.c | core (models, angles) | libm | libc "
              "| libgcc | the library's delta flash |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for key, _, _ in TARGETS:
        r = results[key]
        df = flash(r["floor"]) - flash(r["base"])
        dr = (r["floor"][1] + r["floor"][2]) - (r["base"][1] + r["base"][2])
        bd, bb = r["floorbd"], r["basebd"]
        part = lambda k: bd.get(k, 0) - bb.get(k, 0)  # noqa: E731
        lines.append(f"| {r['label']} | {flash(r['floor'])} | {df} | {dr} "
                     f"| {part('floor')} | {part('gaussfilt')} "
                     f"| {part('libm')} | {part('libc')} | {part('libgcc')} "
                     f"| {flash(r['min']) - flash(r['base'])} |")
    lines.append("")

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
            cells.append(f"{s['text']} / {s['rodata']} / {s['data']} / {s['bss']}")
        name = f"`{mod}.c`" if mod != "total" else "**total**"
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines.append("")

    # Structs.
    lines += ["`sizeof` of the public structs (bytes, float build; the double "
              "build doubles every `gf_real`):", "",
              "| struct | " + " | ".join(results[k]["label"] for k, _, _ in TARGETS) + " |",
              "|---|" + "---|" * len(TARGETS)]
    for st in STRUCTS:
        lines.append(f"| `{st}` | " + " | ".join(
            str(results[k]["structs"][st]) for k, _, _ in TARGETS) + " |")
    lines.append("")

    # Stack.
    lines += ["Worst-case stack depth of every public function (bytes: own "
              "frame from `-fstack-usage`, depth through the deepest call "
              "chain, libm/libc/libgcc included). EKF3's callbacks are counted "
              "as the deepest built-in model; a user model adds "
              "max(0, its own depth - the built-in's) on top of the caller's "
              "frame. A tail call (⇢ in the chains: on Arm a `b.w` with an "
              "R_ARM_THM_JUMP24 relocation, on RISC-V `auipc tN` + `jr tN` "
              "with R_RISCV_CALL_PLT or `j` with R_RISCV_JAL; accepted only "
              "where the disassembly shows the caller's whole frame given back "
              "right before the jump) runs after the caller's frame is "
              "released: depth = max(frame + deepest call, deepest tail call). "
              "Any other jump is counted like a call (its frame on top of the "
              "caller's); Cortex-M0+ code has no tail calls to other "
              "functions.", "",
              "| function | " + " | ".join(
                  f"{results[k]['label']} frame / depth" for k, _, _ in TARGETS)
              + " | deepest chain (Cortex-M4F) |",
              "|---|" + "---|" * len(TARGETS) + "---|"]
    for n in sorted(m4["stack"][0]):
        cells = []
        for key, _, _ in TARGETS:
            f, d, _ = results[key]["stack"][0][n]
            flag = " **!**" if d > STACK_LIMIT else ""
            cells.append(f"{f} / {d}{flag}")
        chain = m4["stack"][0][n][2]
        lines.append(f"| `{n}` | " + " | ".join(cells) + f" | {chain} |")
    lines.append("")
    notes = []
    for key, label, _ in TARGETS:
        _, mism, unknown, guessed = results[key]["stack"]
        if mism:
            notes.append(f"{label}: prologue and .su disagree: " + "; ".join(mism))
        if unknown:
            notes.append(f"{label}: no frame found for " + ", ".join(sorted(unknown))
                         + " (counted as 0)")
        if guessed:
            notes.append(f"{label}: the indirect calls of "
                         + ", ".join(f"`{g}`" for g in sorted(guessed))
                         + " counted as the deepest built-in model.")
    if notes:
        lines += ["Stack analysis notes: " + " ".join(notes), ""]
    else:
        lines += ["Cross-check: for every core function the frame read from "
                  "the disassembly's prologue equals gcc's `.su` figure, on "
                  "all three targets; every callee has a known frame.", ""]
    return "\n".join(lines)


BEGIN = "<!-- firmware:footprint:begin -->"
END = "<!-- firmware:footprint:end -->"


def splice(doc, text):
    s = open(doc).read()
    if BEGIN not in s or END not in s:
        sys.exit(f"{doc}: no {BEGIN} / {END} lines")
    block = f"{BEGIN}\n{text}\n{END}"
    s = s[:s.index(BEGIN)] + block + s[s.index(END) + len(END):]
    open(doc, "w").write(s)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--docs", metavar="FILE")
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    text = report(root, args.build)
    print(text)
    if args.docs:
        splice(args.docs, text)


if __name__ == "__main__":
    main()
