// SPDX-License-Identifier: MIT
/* cmocka's config.h for newlib on a bare-metal Arm target (semihosting via
   rdimon), in place of the one cmocka's own CMake would generate by probing
   the host. What is left out, and why:
   - HAVE_STRUCT_TIMESPEC / HAVE_CLOCK_GETTIME: newlib on bare metal has no
     clock; cmocka then skips its per-test timing (only the printed "ms").
   - HAVE_GCC_THREAD_LOCAL_STORAGE: no thread pointer on bare metal; the
     tests are single-threaded.
   - HAVE_SIGLONGJMP: not in newlib; cmocka falls back to longjmp.
   Signals exist in newlib (signal()/raise()), but a real fault on the
   target is a hardware exception, not a signal: the start-up code's fault
   handler ends QEMU with exit code 3, which fails the ctest test. */
#define PACKAGE "cmocka"
#define VERSION "1.1.5"

#define HAVE_ASSERT_H 1
#define HAVE_INTTYPES_H 1
#define HAVE_MALLOC_H 1
#define HAVE_SETJMP_H 1
#define HAVE_SIGNAL_H 1
#define HAVE_STDARG_H 1
#define HAVE_STDDEF_H 1
#define HAVE_STDINT_H 1
#define HAVE_STDIO_H 1
#define HAVE_STDLIB_H 1
#define HAVE_STRINGS_H 1
#define HAVE_STRING_H 1
#define HAVE_SYS_TYPES_H 1
#define HAVE_TIME_H 1

#define HAVE_CALLOC 1
#define HAVE_EXIT 1
#define HAVE_FPRINTF 1
#define HAVE_SNPRINTF 1
#define HAVE_VSNPRINTF 1
#define HAVE_FREE 1
#define HAVE_LONGJMP 1
#define HAVE_MALLOC 1
#define HAVE_MEMCPY 1
#define HAVE_MEMSET 1
#define HAVE_PRINTF 1
#define HAVE_SETJMP 1
#define HAVE_SIGNAL 1
#define HAVE_STRCMP 1
#define HAVE_STRCPY 1
#define HAVE_STRSIGNAL 1

#define WORDS_SIZEOF_VOID_P 4
