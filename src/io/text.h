/*
 * Numbers as text, for the text formats (internal to vnio): the C locale for
 * the calling thread while a file is read or written, and floating-point
 * values written as the shortest text that reads back as the same value.
 */
#ifndef VN_IO_TEXT_H
#define VN_IO_TEXT_H

#include <stdio.h>

/* strtod and printf follow LC_NUMERIC: in a program that called
 * setlocale(LC_ALL, "") under, say, de_DE, "0.5" would read as 0 and print
 * as "0,5". Text formats always use '.', so the thread that reads or writes
 * one uses the C locale meanwhile. */
typedef struct vn_io_c_locale {
	void* c;        /* locale_t */
	void* previous; /* locale_t */
} vn_io_c_locale;

/* Switches this thread to the C locale; 0 when out of memory. */
int vn_io_c_locale_enter(vn_io_c_locale* l);
/* Restores the thread's previous locale. */
void vn_io_c_locale_leave(vn_io_c_locale* l);

/* A text output that remembers its first failure. */
typedef struct vn_io_text_out {
	FILE* out;
	int failed;
	int error_number; /* errno of the first failed write */
} vn_io_text_out;

/* Writes text unless an earlier write failed. */
void vn_io_put(vn_io_text_out* w, const char* text);
/* " v" with 9 significant digits: enough for a float to read back unchanged. */
void vn_io_put_float9(vn_io_text_out* w, double v);
/* " v" for a float: the shortest of 6 to 9 significant digits that reads back
 * as the same float, so that 0.2 stays "0.2" rather than "0.200000003". */
void vn_io_put_float(vn_io_text_out* w, float v);
/* separator, then v: the shortest of 15, 16 or 17 significant digits that
 * reads back as the same double, so that 0.1 stays "0.1" and every double
 * survives a round trip exactly. */
void vn_io_put_exact(vn_io_text_out* w, const char* separator, double v);

#endif /* VN_IO_TEXT_H */
