// SPDX-License-Identifier: MIT
// gf_route.h: opening LCM with a clear word when udpm has no multicast
// route. LCM's udpm provider tests the route itself (a UDP socket connected
// to the group), but when that fails it frees its context before printing
// the group's address from it (lcm_udpm_create, LCM 1.5), so its "No route
// to A.B.C.D" names whatever that memory holds by then. gf_lcm_open makes
// the same test first and, without a route, says which group and what to
// do, and never calls lcm_create; with one, it is lcm_create. Header-only;
// POSIX sockets (_POSIX_C_SOURCE 200809L).
#ifndef GF_ROUTE_H
#define GF_ROUTE_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <lcm/lcm.h>

// LCM's URL when none is given and LCM_DEFAULT_URL is unset (lcm.h).
#define GF_LCM_DEFAULT_URL "udpm://239.255.76.67:7667"

// gf_udpm_route: 0 if url is not udpm, or its group has a route; otherwise
// -1, with the group's address in group and the reason in why. A URL LCM
// will refuse on its own (a bad address or port) passes: LCM says why.
static int gf_udpm_route(const char *url, char *group, size_t group_len,
                         char *why, size_t why_len)
{
    struct sockaddr_in dest;
    const char *p = url, *end;
    char addr[64];
    long port = 7667;
    size_t len;
    int fd, rc;

    if (p == NULL || *p == '\0') {
        p = getenv("LCM_DEFAULT_URL");
    }
    if (p == NULL || *p == '\0') {
        p = GF_LCM_DEFAULT_URL;
    }
    if (strncmp(p, "udpm://", 7) != 0) {
        return 0;
    }
    p += 7;
    len = strcspn(p, ":?");
    if (len == 0) {
        p = GF_LCM_DEFAULT_URL + 7;
        len = strcspn(p, ":?");
    }
    if (len >= sizeof addr) {
        return 0;
    }
    memcpy(addr, p, len);
    addr[len] = '\0';
    end = p + len;
    if (*end == ':') {
        char *stop = NULL;
        port = strtol(end + 1, &stop, 10);
        if (stop == end + 1 || port < 0 || port > 65535) {
            return 0;
        }
    }
    memset(&dest, 0, sizeof dest);
    dest.sin_family = AF_INET;
    dest.sin_port = htons((uint16_t)port);
    if (inet_pton(AF_INET, addr, &dest.sin_addr) != 1) {
        return 0;
    }
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) {
        return 0; // no socket at all: LCM says so itself
    }
    rc = connect(fd, (const struct sockaddr *)&dest, sizeof dest);
    if (rc != 0) {
        snprintf(why, why_len, "%s", strerror(errno));
    }
    close(fd);
    if (rc == 0) {
        return 0;
    }
    snprintf(group, group_len, "%s", addr);
    return -1;
}

// gf_lcm_open: lcm_create(url) once its udpm group has a route; without
// one, says so on stderr as "prog: ..." with the fix, and returns NULL.
static lcm_t *gf_lcm_open(const char *prog, const char *url)
{
    char group[64], why[128];
    if (gf_udpm_route(url, group, sizeof group, why, sizeof why) != 0) {
        fprintf(stderr,
                "%s: no route to the multicast group %s of %s (%s): udpm "
                "needs one; on one machine, as root: ip route add "
                "224.0.0.0/4 dev lo (across machines: dev IFACE; "
                "docs/node.md)\n",
                prog, group,
                url != NULL && *url != '\0' ? url : "LCM's default URL", why);
        return NULL;
    }
    return lcm_create(url);
}

#endif
