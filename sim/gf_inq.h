// SPDX-License-Identifier: MIT
// gf_inq.h: gf_node's input queue, between LCM's dispatch and the thread
// that filters and publishes. Header-only, POSIX threads; one producer
// (the thread that calls lcm_handle) and one consumer.
//
// Why a queue of our own: LCM drops a message whose subscription's queue
// is full inside its receive thread and tells no one, so such a loss
// showed only as a seq gap, like a loss on the wire. Here LCM's own limit
// is off and its handler only copies each message into this queue, which
// has a fixed size (set at start, touched once so that it is resident):
// a message that finds it full is dropped and counted (gf_inq.dropped,
// the node's dropped=). A log replay (file://) never drops: its producer
// waits for room instead.
//
// Entries are packed in a byte ring (header, channel, payload, 8-byte
// aligned); a payload longer than GF_INQ_MAX_DATA is queued without its
// bytes (the node calls it malformed: it reads none that long,
// node_core.h's GF_NODE_MAX_LEN).
#ifndef GF_INQ_H
#define GF_INQ_H

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define GF_INQ_MAX_DATA 131072
// Bytes per message the ring is sized for (an input is about 150 bytes
// with its header and channel).
#define GF_INQ_BYTES_PER_MSG 256u

typedef struct gf_inq_entry {
    uint32_t size;      // of the whole entry, aligned
    uint32_t len;       // of the payload as received
    int64_t recv_utime; // LCM's receive time
    uint8_t has_data;   // 0: payload longer than GF_INQ_MAX_DATA, not kept
    uint8_t chlen;
    uint8_t pad[6];
    // then channel (chlen bytes + NUL), then the payload
} gf_inq_entry;

typedef struct gf_inq {
    pthread_mutex_t mu;
    pthread_cond_t nonempty, nonfull;
    uint8_t *buf;
    size_t cap, head, tail, wrap; // wrap: where the data before 0 ends
    unsigned count, max_count, peak;
    int block; // wait for room instead of dropping (log replay)
    int closed;
    uint64_t dropped;
} gf_inq;

#define GF_INQ_NO_WRAP ((size_t)-1)

// A queue of max_count messages. Returns 0, or -1 (no memory).
static inline int gf_inq_init(gf_inq *q, unsigned max_count, int block)
{
    memset(q, 0, sizeof(*q));
    q->cap = (size_t)max_count * GF_INQ_BYTES_PER_MSG;
    if (q->cap < 2 * (sizeof(gf_inq_entry) + 256 + GF_INQ_MAX_DATA)) {
        q->cap = 2 * (sizeof(gf_inq_entry) + 256 + GF_INQ_MAX_DATA);
    }
    q->buf = (uint8_t *)malloc(q->cap);
    if (q->buf == NULL) {
        return -1;
    }
    memset(q->buf, 0, q->cap); // resident from the start
    q->max_count = max_count;
    q->block = block;
    q->wrap = GF_INQ_NO_WRAP;
    pthread_mutex_init(&q->mu, NULL);
    pthread_cond_init(&q->nonempty, NULL);
    pthread_cond_init(&q->nonfull, NULL);
    return 0;
}

static inline void gf_inq_free(gf_inq *q)
{
    pthread_mutex_destroy(&q->mu);
    pthread_cond_destroy(&q->nonempty);
    pthread_cond_destroy(&q->nonfull);
    free(q->buf);
    q->buf = NULL;
}

// Where an entry of s bytes goes, or NULL if it does not fit now
// (q->mu held). Moves tail/wrap as if written.
static inline uint8_t *gf_inq_room(gf_inq *q, size_t s)
{
    uint8_t *p;
    if (q->count >= q->max_count) {
        return NULL;
    }
    if (q->wrap == GF_INQ_NO_WRAP) {
        if (q->cap - q->tail >= s) {
            p = q->buf + q->tail;
            q->tail += s;
            return p;
        }
        if (s > q->head) {
            return NULL;
        }
        q->wrap = q->tail;
        q->tail = s;
        return q->buf;
    }
    if (q->head - q->tail < s) {
        return NULL;
    }
    p = q->buf + q->tail;
    q->tail += s;
    return p;
}

// Copies one message in; returns 0, or -1 if it was dropped (counted).
static inline int gf_inq_push(gf_inq *q, const char *channel, const void *data,
                              uint32_t len, int64_t recv_utime)
{
    size_t chlen = strlen(channel), s;
    int keep = len <= GF_INQ_MAX_DATA;
    uint8_t *p;
    gf_inq_entry e;
    if (chlen > 255) {
        chlen = 255;
    }
    s = sizeof(gf_inq_entry) + chlen + 1 + (keep ? len : 0);
    s = (s + 7u) & ~(size_t)7u;
    pthread_mutex_lock(&q->mu);
    while ((p = gf_inq_room(q, s)) == NULL) {
        if (!q->block || q->closed) {
            q->dropped++;
            pthread_mutex_unlock(&q->mu);
            return -1;
        }
        pthread_cond_wait(&q->nonfull, &q->mu);
    }
    memset(&e, 0, sizeof e);
    e.size = (uint32_t)s;
    e.len = len;
    e.recv_utime = recv_utime;
    e.has_data = (uint8_t)keep;
    e.chlen = (uint8_t)chlen;
    memcpy(p, &e, sizeof e);
    memcpy(p + sizeof e, channel, chlen);
    p[sizeof e + chlen] = '\0';
    if (keep && len > 0) {
        memcpy(p + sizeof e + chlen + 1, data, len);
    }
    q->count++;
    if (q->count > q->peak) {
        q->peak = q->count;
    }
    pthread_cond_signal(&q->nonempty);
    pthread_mutex_unlock(&q->mu);
    return 0;
}

// The oldest entry, waiting for one; NULL once closed and empty. The
// entry stays valid until gf_inq_release.
static inline const gf_inq_entry *gf_inq_peek(gf_inq *q)
{
    const gf_inq_entry *e;
    pthread_mutex_lock(&q->mu);
    while (q->count == 0 && !q->closed) {
        pthread_cond_wait(&q->nonempty, &q->mu);
    }
    if (q->count == 0) {
        pthread_mutex_unlock(&q->mu);
        return NULL;
    }
    if (q->wrap != GF_INQ_NO_WRAP && q->head == q->wrap) {
        q->head = 0;
        q->wrap = GF_INQ_NO_WRAP;
    }
    e = (const gf_inq_entry *)(const void *)(q->buf + q->head);
    pthread_mutex_unlock(&q->mu);
    return e;
}

static inline void gf_inq_release(gf_inq *q, const gf_inq_entry *e)
{
    pthread_mutex_lock(&q->mu);
    q->head += e->size;
    q->count--;
    if (q->wrap != GF_INQ_NO_WRAP && q->head == q->wrap) {
        q->head = 0;
        q->wrap = GF_INQ_NO_WRAP;
    }
    if (q->count == 0 && q->wrap == GF_INQ_NO_WRAP) {
        q->head = q->tail = 0;
    }
    pthread_cond_signal(&q->nonfull);
    pthread_mutex_unlock(&q->mu);
}

static inline const char *gf_inq_channel(const gf_inq_entry *e)
{
    return (const char *)(const void *)(e + 1);
}

static inline const void *gf_inq_data(const gf_inq_entry *e)
{
    return e->has_data ? (const uint8_t *)(const void *)(e + 1) + e->chlen + 1
                       : NULL;
}

// No more pushes; the consumer drains what is left, then gets NULL.
static inline void gf_inq_close(gf_inq *q)
{
    pthread_mutex_lock(&q->mu);
    q->closed = 1;
    pthread_cond_broadcast(&q->nonempty);
    pthread_cond_broadcast(&q->nonfull);
    pthread_mutex_unlock(&q->mu);
}

#endif
