// SPDX-License-Identifier: MIT
// gf_sock.h: LCM's udpm receive socket of this process, found from the
// outside (LCM 1.5 does not hand it out): its buffer, and the datagrams
// the kernel dropped because that buffer was full. Header-only, Linux
// (SO_MEMINFO); gf_node and the tests' recorder use it.
//
// Why: a datagram the kernel drops never reaches LCM, so no counter of
// the program sees it; a loss inside a track's stream shows as a seq gap,
// one at its end as nothing at all. The socket itself counts them
// (SK_MEMINFO_DROPS: what /proc/net/udp's drops column shows).
#ifndef GF_SOCK_H
#define GF_SOCK_H

#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>

#include <arpa/inet.h>
#include <linux/sock_diag.h> // SK_MEMINFO_DROPS
#include <netinet/in.h>
#include <sys/socket.h>

// SO_MEMINFO (Linux 3.13) where libc's headers lack it.
#ifndef SO_MEMINFO
#define SO_MEMINFO 55
#endif

// LCM's udpm receive socket: the datagram socket of this process bound to
// a multicast address (224.0.0.0/4; the sending socket is not). -1 if
// there is none (another provider: file://, memq://).
static inline int gf_sock_udpm(void)
{
    DIR *d = opendir("/proc/self/fd");
    struct dirent *ent;
    int found = -1;
    if (d == NULL) {
        return -1;
    }
    while (found < 0 && (ent = readdir(d)) != NULL) {
        struct sockaddr_in a;
        socklen_t len = sizeof a;
        int fd, type = 0;
        socklen_t tlen = sizeof type;
        char *end;
        long v = strtol(ent->d_name, &end, 10);
        if (*end != '\0' || end == ent->d_name || v < 0) {
            continue;
        }
        fd = (int)v;
        if (getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &tlen) != 0 ||
            type != SOCK_DGRAM) {
            continue;
        }
        if (getsockname(fd, (struct sockaddr *)&a, &len) != 0 ||
            a.sin_family != AF_INET) {
            continue;
        }
        if ((ntohl(a.sin_addr.s_addr) & 0xf0000000u) == 0xe0000000u) {
            found = fd;
        }
    }
    closedir(d);
    return found;
}

// The socket's receive buffer as the kernel holds it (SO_RCVBUF: Linux
// reports twice what was set, its bookkeeping included), or -1.
static inline long gf_sock_rcvbuf(int fd)
{
    int v = 0;
    socklen_t len = sizeof v;
    if (fd < 0 || getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &v, &len) != 0) {
        return -1;
    }
    return (long)v;
}

// Datagrams the kernel dropped for fd because its buffer was full; -1 if
// it cannot say.
static inline long gf_sock_drops(int fd)
{
    uint32_t mem[SK_MEMINFO_VARS];
    socklen_t len = sizeof mem;
    if (fd < 0 || getsockopt(fd, SOL_SOCKET, SO_MEMINFO, mem, &len) != 0 ||
        len < (socklen_t)((SK_MEMINFO_DROPS + 1) * sizeof mem[0])) {
        return -1;
    }
    return (long)mem[SK_MEMINFO_DROPS];
}

#endif
