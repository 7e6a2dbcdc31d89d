/* Small helpers shared by the command-line programs (header-only: each
 * program is one translation unit plus the libraries). */
#ifndef VN_TOOLS_COMMON_H
#define VN_TOOLS_COMMON_H

/* clock_gettime, isatty and sysconf are POSIX, not C11. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "vn.h"
#include "vn_io.h"

/* One line on stderr, "PROG: error: ...", then exit(status): every failure
 * of the tools ends this way. fmt has one %s, for arg. */
static inline void tool_die(const char* prog, int status, const char* fmt, const char* arg)
{
	fprintf(stderr, "%s: error: ", prog);
	fprintf(stderr, fmt, arg);
	fputc('\n', stderr);
	exit(status);
}

static inline double tool_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline unsigned tool_cpu_count(void)
{
	long n = sysconf(_SC_NPROCESSORS_ONLN);
	return n > 0 ? (unsigned)n : 1;
}

/* Exits with 1 unless the library this program runs with has the major and
 * minor version it was compiled against (vn.h: the ABI before 1.0). */
static inline void tool_check_version(const char* prog)
{
	if (vn_version() >> 8 != VN_VERSION >> 8) {
		fprintf(stderr, "%s: error: built for libvn %s but running with %s\n", prog, VN_VERSION_STRING,
		        vn_version_string());
		exit(1);
	}
}

/* One line per scheme: name (padded to the longest), description, [reference]. */
static inline void tool_list_methods(FILE* out)
{
	int width = 0;
	for (unsigned m = 0; m < vn_method_count; ++m)
		width = (int)strlen(vn_method_name((vn_method)m)) > width ? (int)strlen(vn_method_name((vn_method)m)) : width;
	for (unsigned m = 0; m < vn_method_count; ++m)
		fprintf(out, "%-*s %s [%s]\n", width, vn_method_name((vn_method)m), vn_method_description((vn_method)m),
		        vn_method_reference((vn_method)m));
}

#endif /* VN_TOOLS_COMMON_H */
