// SPDX-License-Identifier: MIT
// gf_setmodel: sets one track's model in a running gf_node, by publishing
// a model_t (lcm_types/model_t.lcm) on GF_MODEL_<track>.
//
//   gf_setmodel --model NAME --track N [--config FILE] [--reset]
//               [--utime US] [--url URL]
//
// NAME is a model of FILE (a gf_node configuration, docs/node.md) or a
// preset (book-car, book-robot). --reset restarts the track's belief from
// the model's prior; without it the track keeps its belief and runs its
// next inputs with the new model. A linear model's numbers are the node's
// own configuration: for one, gf_setmodel only resets the track to its
// configured prior (--reset). --utime: the message's utime (default 0;
// the belief a reset publishes carries it).
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include "gaussfilt_lcm_model_t.h"
#include "gf_channels.h"
#include "gf_route.h"
#include "node_model.h"

static const char usage_text[] =
    "usage: gf_setmodel --model NAME --track N [--config FILE] [--reset]\n"
    "                   [--utime US] [--url URL]\n";

int main(int argc, char **argv)
{
    static gf_node_config cfg;
    const char *url = NULL, *path = NULL, *name = NULL;
    const gf_node_model *mdl;
    gaussfilt_lcm_model_t m;
    char channel[GF_CHANNEL_MAX], err[256];
    uint8_t buf[512];
    long track = 0;
    long long utime = 0;
    int i, have_track = 0, reset = 0, len, rc;
    lcm_t *lcm;

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0) {
            fputs("gf_setmodel: sets one track's model in a running gf_node "
                  "(model_t on GF_MODEL_<track>).\n\n",
                  stdout);
            fputs(usage_text, stdout);
            fputs("\n  --model NAME   a model of --config, or book-car / "
                  "book-robot\n"
                  "  --track N      the track\n"
                  "  --config FILE  a gf_node configuration (docs/node.md)\n"
                  "  --reset        restart the belief from the model's "
                  "prior (a\n"
                  "                 linear model: the only thing sent, "
                  "from the node's\n"
                  "                 own configuration)\n"
                  "  --utime US     the message's utime (default 0)\n"
                  "  --url URL      LCM URL (default: LCM's)\n\n"
                  "example:\n  gf_setmodel --config car100.conf --model "
                  "car100 --track 7 --reset\n",
                  stdout);
            return 0;
        } else if (strcmp(argv[i], "--reset") == 0) {
            reset = 1;
        } else if (i + 1 < argc && strcmp(argv[i], "--model") == 0) {
            name = argv[++i];
        } else if (i + 1 < argc && strcmp(argv[i], "--config") == 0) {
            path = argv[++i];
        } else if (i + 1 < argc && strcmp(argv[i], "--utime") == 0) {
            utime = strtoll(argv[++i], NULL, 0);
        } else if (i + 1 < argc && strcmp(argv[i], "--url") == 0) {
            url = argv[++i];
        } else if (i + 1 < argc && strcmp(argv[i], "--track") == 0) {
            track = atol(argv[++i]);
            have_track = 1;
        } else {
            fputs(usage_text, stderr);
            return 2;
        }
    }
    if (name == NULL || !have_track) {
        fputs(usage_text, stderr);
        return 2;
    }
    if (path != NULL && gf_node_config_load(&cfg, path, err, sizeof err)) {
        fprintf(stderr, "gf_setmodel: %s\n", err);
        return 2;
    }
    mdl = gf_node_config_find(&cfg, name);
    if (mdl == NULL) {
        fprintf(stderr, "gf_setmodel: no model %s\n", name);
        return 2;
    }
    if (mdl->kind == GF_NODE_KIND_LINEAR && !reset) {
        fprintf(stderr,
                "gf_setmodel: model %s is linear: its numbers are the node's "
                "configuration; --reset restarts track %ld from its prior\n",
                name, track);
        return 2;
    }
    memset(&m, 0, sizeof m);
    m.utime = (int64_t)utime;
    m.track = (int32_t)track;
    m.model = mdl->kind;
    m.measure = mdl->measure;
    m.dt = mdl->dt;
    m.accel_var = mdl->accel_var;
    memcpy(m.odometry, mdl->odometry, sizeof m.odometry);
    memcpy(m.landmark, mdl->landmark, sizeof m.landmark);
    m.gate = mdl->gate;
    m.reset = (int8_t)reset;
    memcpy(m.prior_mean, mdl->prior_mean, sizeof m.prior_mean);
    memcpy(m.prior_cov, mdl->prior_cov, sizeof m.prior_cov);
    len = gaussfilt_lcm_model_t_encode(buf, 0, (int)sizeof buf, &m);
    snprintf(channel, sizeof channel, "%s%ld", GF_CHANNEL_MODEL, track);
    lcm = gf_lcm_open("gf_setmodel", url);
    if (lcm == NULL || len < 0) {
        fprintf(stderr, "gf_setmodel: cannot open LCM at %s\n",
                url ? url : "(default URL)");
        return 1;
    }
    rc = lcm_publish(lcm, channel, buf, (unsigned)len);
    printf("gf_setmodel: %s model=%s%s%s\n", channel, name,
           reset ? " reset" : "", rc == 0 ? "" : " (publish FAILED)");
    lcm_destroy(lcm);
    gf_node_config_free(&cfg);
    return rc == 0 ? 0 : 1;
}
