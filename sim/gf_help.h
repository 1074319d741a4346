// SPDX-License-Identifier: MIT
// gf_help.h: --help for sim's programs. Header-only.
//
//   gf_help(argc, argv, text): if any argument is --help or -h, prints
//   text (what the program does, its options, an example) on stdout and
//   exits 0.
#ifndef GF_HELP_H
#define GF_HELP_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static inline void gf_help(int argc, char **argv, const char *text)
{
    int i;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(text, stdout);
            exit(0);
        }
    }
}

#endif
