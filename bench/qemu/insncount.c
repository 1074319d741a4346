// SPDX-License-Identifier: MIT
// insncount: a QEMU TCG plugin that counts the guest instructions executed
// between two marked addresses, for the Cortex-M4F benchmark image
// (bench/m4f.c). Debian's qemu 7.2 installs no plugin header, so the few
// functions of the plugin API used here are declared below, as that
// release's include/qemu/qemu-plugin.h has them (plugin API version 1).
//
//   qemu-system-arm -M mps2-an386 ... -d plugin -D log
//       -plugin libinsncount.so,start=0xA,stop=0xB,report=0xC[,call=0xD...]
//
// start, stop, report: entry addresses of the image's three marker
// functions (nm; the Thumb bit is ignored). Executing start's first
// instruction opens a region, stop's closes it; neither of those two
// instructions is counted, everything executed in between is (the caller's
// `bl` to stop included: an empty region counts 1). report prints, and then
// clears, the totals of the regions since the previous report:
//
//   insncount: regions R insns N vdiv D vsqrt S calls C
//
// vdiv and vsqrt are the VDIV.F32 and VSQRT.F32 among the N instructions
// (14 cycles each on a Cortex-M4F, against 1 for most others; one in an IT
// block is counted whether or not its condition passes: this API cannot
// read the flags, so the figure is an upper bound); calls counts
// how often the entries given as call= (up to 64: soft-float helpers such as
// __aeabi_ddiv, a libm function) were entered inside the regions. At exit
// the plugin prints the instructions executed by the whole run:
//
//   insncount: total T reports P
//
// profile=on: each report is preceded by one line per instruction address
// executed in its regions, with how often it was (a profile, for
// bench/qemu/profile.py to sum by function):
//
//   insncount: pc 0xADDR COUNT
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---- the plugin API of qemu 7.2 (QEMU_PLUGIN_VERSION 1) ---------------------

#define QEMU_PLUGIN_EXPORT __attribute__((visibility("default")))

typedef uint64_t qemu_plugin_id_t;

typedef struct qemu_info_t {
    const char *target_name;
    struct {
        int min;
        int cur;
    } version;
    bool system_emulation;
    union {
        struct {
            int smp_vcpus;
            int max_vcpus;
        } system;
    };
} qemu_info_t;

struct qemu_plugin_tb;
struct qemu_plugin_insn;

enum qemu_plugin_cb_flags {
    QEMU_PLUGIN_CB_NO_REGS,
    QEMU_PLUGIN_CB_R_REGS,
    QEMU_PLUGIN_CB_RW_REGS,
};

typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);
typedef void (*qemu_plugin_vcpu_udata_cb_t)(unsigned int vcpu_index,
                                            void *userdata);
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id,
                                               struct qemu_plugin_tb *tb);

void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id,
                                           qemu_plugin_vcpu_tb_trans_cb_t cb);
void qemu_plugin_register_vcpu_insn_exec_cb(struct qemu_plugin_insn *insn,
                                            qemu_plugin_vcpu_udata_cb_t cb,
                                            enum qemu_plugin_cb_flags flags,
                                            void *userdata);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
struct qemu_plugin_insn *
qemu_plugin_tb_get_insn(const struct qemu_plugin_tb *tb, size_t idx);
const void *qemu_plugin_insn_data(const struct qemu_plugin_insn *insn);
size_t qemu_plugin_insn_size(const struct qemu_plugin_insn *insn);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn *insn);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id,
                                    qemu_plugin_udata_cb_t cb, void *userdata);
void qemu_plugin_outs(const char *string);

QEMU_PLUGIN_EXPORT int qemu_plugin_version = 1;
QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id,
                                           const qemu_info_t *info, int argc,
                                           char **argv);

// ---- the counter -------------------------------------------------------------

// What an instruction is, passed to its callback as the user data.
enum kind {
    K_PLAIN,
    K_VDIV,
    K_VSQRT,
    K_START,
    K_STOP,
    K_REPORT,
    K_CALL, // K_CALL + i: the entry of call[i]
};

#define MAX_CALLS 64

static uint64_t mark_start, mark_stop, mark_report;
static uint64_t call_addr[MAX_CALLS];
static unsigned n_calls;

static bool active;
static uint64_t regions, insns, vdivs, vsqrts, calls;
static uint64_t total, reports;
static bool profile;

// One record per guest instruction address, found again when a block is
// translated anew; the callbacks get a pointer to it.
struct insn_rec {
    uint64_t pc;
    uint64_t count; // executions inside regions since the last report
    unsigned kind;
    bool used;
};

#define TABLE_BITS 17
#define TABLE_SIZE (1u << TABLE_BITS)
static struct insn_rec *table;

static struct insn_rec *record(uint64_t pc, unsigned kind)
{
    size_t i = (size_t)((pc >> 1) * 0x9E3779B97F4A7C15ull >> (64 - TABLE_BITS));
    for (size_t probes = 0; probes < TABLE_SIZE; probes++) {
        struct insn_rec *r = &table[i];
        if (!r->used) {
            r->used = true;
            r->pc = pc;
            r->kind = kind;
            return r;
        }
        if (r->pc == pc) {
            return r;
        }
        i = (i + 1) & (TABLE_SIZE - 1);
    }
    fprintf(stderr, "insncount: more than %u instruction addresses\n",
            TABLE_SIZE);
    abort();
}

// The kind of a Thumb instruction from its bytes (little-endian halfwords):
// VDIV.F32 is EE80 0A00 under the mask FFB0 0F50 (D, Vn, Vd, N, M, Vm
// free; sz = 0), VSQRT.F32 is EEB1 0AC0 under FFBF 0FD0. The instruction
// is the first 4 bytes: near the end of a page qemu 7.2 reads the next
// halfword to see whether the next instruction crosses it, and that read
// lands in this instruction's bytes (size 6). (A 16-bit instruction, 2
// bytes or 4 with such a read, never matches: its first halfword is not
// the start of a 32-bit encoding, as EExx is.)
static enum kind classify(const uint8_t *b, size_t size)
{
    if (size < 4) {
        return K_PLAIN;
    }
    const unsigned hw1 = (unsigned)b[0] | (unsigned)b[1] << 8;
    const unsigned hw2 = (unsigned)b[2] | (unsigned)b[3] << 8;
    if ((hw1 & 0xFFB0u) == 0xEE80u && (hw2 & 0x0F50u) == 0x0A00u) {
        return K_VDIV;
    }
    if ((hw1 & 0xFFBFu) == 0xEEB1u && (hw2 & 0x0FD0u) == 0x0AC0u) {
        return K_VSQRT;
    }
    return K_PLAIN;
}

static void print_profile(void)
{
    char line[80];
    for (size_t i = 0; i < TABLE_SIZE; i++) {
        struct insn_rec *r = &table[i];
        if (r->used && r->count) {
            snprintf(line, sizeof line, "insncount: pc 0x%llx %llu\n",
                     (unsigned long long)r->pc, (unsigned long long)r->count);
            qemu_plugin_outs(line);
            r->count = 0;
        }
    }
}

static void on_insn(unsigned int vcpu, void *udata)
{
    (void)vcpu;
    struct insn_rec *rec = udata;
    const unsigned k = rec->kind;
    total++;
    switch (k) {
    case K_START:
        active = true;
        regions++;
        return;
    case K_STOP:
        active = false;
        return;
    case K_REPORT: {
        char line[160];
        if (profile) {
            print_profile();
        }
        snprintf(line, sizeof line,
                 "insncount: regions %llu insns %llu vdiv %llu vsqrt %llu "
                 "calls %llu\n",
                 (unsigned long long)regions, (unsigned long long)insns,
                 (unsigned long long)vdivs, (unsigned long long)vsqrts,
                 (unsigned long long)calls);
        qemu_plugin_outs(line);
        regions = insns = vdivs = vsqrts = calls = 0;
        reports++;
        return;
    }
    default:
        break;
    }
    if (!active) {
        return;
    }
    insns++;
    rec->count++;
    if (k == K_VDIV) {
        vdivs++;
    } else if (k == K_VSQRT) {
        vsqrts++;
    } else if (k >= K_CALL) {
        calls++;
    }
}

static void on_tb_trans(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    (void)id;
    const size_t n = qemu_plugin_tb_n_insns(tb);
    for (size_t i = 0; i < n; i++) {
        struct qemu_plugin_insn *insn = qemu_plugin_tb_get_insn(tb, i);
        const uint64_t pc = qemu_plugin_insn_vaddr(insn) & ~(uint64_t)1;
        unsigned k =
            classify(qemu_plugin_insn_data(insn), qemu_plugin_insn_size(insn));
        if (pc == mark_start) {
            k = K_START;
        } else if (pc == mark_stop) {
            k = K_STOP;
        } else if (pc == mark_report) {
            k = K_REPORT;
        } else {
            for (unsigned c = 0; c < n_calls; c++) {
                if (pc == call_addr[c]) {
                    k = K_CALL + c;
                }
            }
        }
        qemu_plugin_register_vcpu_insn_exec_cb(
            insn, on_insn, QEMU_PLUGIN_CB_NO_REGS, record(pc, k));
    }
}

static void on_exit(qemu_plugin_id_t id, void *udata)
{
    (void)id;
    (void)udata;
    char line[96];
    snprintf(line, sizeof line, "insncount: total %llu reports %llu\n",
             (unsigned long long)total, (unsigned long long)reports);
    qemu_plugin_outs(line);
}

// An address argument: "0x..." (or decimal), the Thumb bit dropped.
static int parse_addr(const char *s, uint64_t *out)
{
    char *end;
    unsigned long long v = strtoull(s, &end, 0);
    if (*s == '\0' || *end != '\0' || v == 0) {
        return -1;
    }
    *out = (uint64_t)v & ~(uint64_t)1;
    return 0;
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id,
                                           const qemu_info_t *info, int argc,
                                           char **argv)
{
    (void)info;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        int bad = 0;
        if (strncmp(a, "start=", 6) == 0) {
            bad = parse_addr(a + 6, &mark_start);
        } else if (strncmp(a, "stop=", 5) == 0) {
            bad = parse_addr(a + 5, &mark_stop);
        } else if (strncmp(a, "report=", 7) == 0) {
            bad = parse_addr(a + 7, &mark_report);
        } else if (strcmp(a, "profile=on") == 0) {
            profile = true;
        } else if (strncmp(a, "call=", 5) == 0) {
            bad = n_calls == MAX_CALLS ||
                  parse_addr(a + 5, &call_addr[n_calls++]);
        } else {
            bad = 1;
        }
        if (bad) {
            fprintf(stderr,
                    "insncount: bad argument '%s' (start=, stop=, "
                    "report=, call= take an address; profile=on)\n",
                    a);
            return -1;
        }
    }
    if (!mark_start || !mark_stop || !mark_report) {
        fprintf(stderr, "insncount: start=, stop= and report= are needed\n");
        return -1;
    }
    table = calloc(TABLE_SIZE, sizeof *table);
    if (!table) {
        return -1;
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb_trans);
    qemu_plugin_register_atexit_cb(id, on_exit, NULL);
    return 0;
}
