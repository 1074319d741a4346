// SPDX-License-Identifier: MIT
// gf_logcmp: compares the events of LCM log files, channel and payload
// byte for byte (the log's own timestamps are ignored: they are the time of
// writing).
//
//   gf_logcmp [--prefix P] [--expect N] LOG [LOG2]
//
// Counts the events whose channel starts with P (default: all). With LOG2,
// those events must be identical in both logs, in order. --expect N: the
// count must be exactly N. Exit 0 when all holds.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/eventlog.h>
#include "gf_help.h"

// Next event whose channel starts with prefix, or NULL at the end.
static lcm_eventlog_event_t *next(lcm_eventlog_t *log, const char *prefix)
{
    lcm_eventlog_event_t *e;
    while ((e = lcm_eventlog_read_next_event(log)) != NULL) {
        if (strncmp(e->channel, prefix, strlen(prefix)) == 0) {
            return e;
        }
        lcm_eventlog_free_event(e);
    }
    return NULL;
}

static const char help_text[] =
    "gf_logcmp: counts the events of an LCM log whose channel starts with a\n"
    "prefix, or compares two logs event by event (channel and payload "
    "bytes).\n\n"
    "usage: gf_logcmp [--prefix P] [--expect N] LOG [LOG2]\n\n"
    "  --prefix P      only channels starting with P (default: all)\n"
    "  --expect N      the count must be exactly N\n"
    "  LOG2            the events must be identical to LOG's, in order\n\n"
    "example:\n"
    "  gf_logcmp --prefix GF_BELIEF_ replay-a.lcmlog replay-b.lcmlog\n";

int main(int argc, char **argv)
{
    const char *prefix = "", *path[2] = {NULL, NULL};
    long expect = -1, count = 0;
    int i, npath = 0, diff = 0;
    lcm_eventlog_t *log[2] = {NULL, NULL};

    gf_help(argc, argv, help_text);
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--prefix") == 0 && i + 1 < argc) {
            prefix = argv[++i];
        } else if (strcmp(argv[i], "--expect") == 0 && i + 1 < argc) {
            expect = atol(argv[++i]);
        } else if (npath < 2) {
            path[npath++] = argv[i];
        } else {
            npath = 3;
        }
    }
    if (npath < 1 || npath > 2) {
        fprintf(stderr, "usage: gf_logcmp [--prefix P] [--expect N] LOG "
                        "[LOG2]\n");
        return 2;
    }
    for (i = 0; i < npath; i++) {
        log[i] = lcm_eventlog_create(path[i], "r");
        if (log[i] == NULL) {
            fprintf(stderr, "gf_logcmp: cannot read %s\n", path[i]);
            return 1;
        }
    }
    for (;;) {
        lcm_eventlog_event_t *a = next(log[0], prefix);
        lcm_eventlog_event_t *b = npath == 2 ? next(log[1], prefix) : NULL;
        if (a == NULL && b == NULL) {
            break;
        }
        if (npath == 2 &&
            (a == NULL || b == NULL || strcmp(a->channel, b->channel) != 0 ||
             a->datalen != b->datalen ||
             memcmp(a->data, b->data, (size_t)a->datalen) != 0)) {
            if (!diff) {
                fprintf(stderr, "gf_logcmp: event %ld differs (%s vs %s)\n",
                        count, a ? a->channel : "end of log",
                        b ? b->channel : "end of log");
            }
            diff = 1;
        }
        if (a != NULL) {
            lcm_eventlog_free_event(a);
        }
        if (b != NULL) {
            lcm_eventlog_free_event(b);
        }
        count++;
    }
    for (i = 0; i < npath; i++) {
        lcm_eventlog_destroy(log[i]);
    }
    printf("gf_logcmp: %ld events on '%s*'%s%s\n", count, prefix,
           npath == 2 ? (diff ? ", logs DIFFER" : ", identical in both logs")
                      : "",
           expect >= 0 && count != expect ? " (UNEXPECTED COUNT)" : "");
    if (expect >= 0 && count != expect) {
        fprintf(stderr, "gf_logcmp: expected %ld events\n", expect);
        return 1;
    }
    return diff;
}
