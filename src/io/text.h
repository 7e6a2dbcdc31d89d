/*
 * Numbers as text, for the text formats (internal to vnio): the C locale for
 * the calling thread while a file is read or written, and floating-point
 * values written as the shortest text that reads back as the same value.
 */
#ifndef VN_IO_TEXT_H
#define VN_IO_TEXT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "vn_io.h"

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

/* A text output that remembers its first failure. It gathers the text in
 * its own buffer, one fwrite a buffer: a call into stdio per number (which
 * locks the stream each time) cost a sixth of writing an OBJ. Made as
 * {out, 0, 0, 0, {0}}; vn_io_flush must end it. */
typedef struct vn_io_text_out {
	FILE* out;
	int failed;
	int error_number; /* errno of the first failed write */
	size_t used;      /* bytes in buffer */
	char buffer[16384];
} vn_io_text_out;

/* Writes text unless an earlier write failed. */
void vn_io_put(vn_io_text_out* w, const char* text);
/* Each line of comments (vn_io_mesh.comments; NULL: none) after prefix
 * ("#", "comment "), a line each. */
void vn_io_put_comments(vn_io_text_out* w, const char* comments, const char* prefix);
/* `before`, then v in decimal: an index or a count without printf, which
 * took half of writing an OBJ's faces. */
void vn_io_put_uint(vn_io_text_out* w, const char* before, uint64_t v);
/* Writes what the buffer holds; returns 0 where some write failed
 * (w->error_number says why). */
int vn_io_flush(vn_io_text_out* w);
/* " v" with 9 significant digits: enough for a float to read back unchanged. */
void vn_io_put_float9(vn_io_text_out* w, double v);
/* " v" for a float: the shortest of 6 to 9 significant digits that reads back
 * as the same float, so that 0.2 stays "0.2" rather than "0.200000003". */
void vn_io_put_float(vn_io_text_out* w, float v);
/* v as vn_io_format_exact writes it, after a space where `space` is set. */
void vn_io_put_exact(vn_io_text_out* w, int space, double v);

/* Room for any number vn_io_format_g or vn_io_format_exact writes, with
 * its terminating NUL. */
#define VN_IO_NUMBER_SIZE 32
/* The text of snprintf(out, VN_IO_NUMBER_SIZE, "%.*g", digits, v), byte for
 * byte; returns its length. Where v is finite and not far from 1 (about
 * 1e-9 <= |v| < 1e8 at 9 digits, 1e-11 <= |v| < 1e15 at 17: 128-bit
 * integers then hold v's exact value times the power of 10 that leaves
 * `digits` digits), they are rounded there as printf rounds them, without
 * printf's arbitrary precision, which made a text file of a million
 * numbers take seconds to write. */
size_t vn_io_format_g(char* out, double v, int digits);
/* v as the shortest of 15, 16 or 17 significant digits ("%.*g") that reads
 * back as the same double, so that 0.1 stays "0.1" and every double
 * survives a round trip exactly; returns the length. Whether it reads back
 * is decided exactly in integers where vn_io_format_g rounds in them, by
 * strtod elsewhere. */
size_t vn_io_format_exact(char* out, double v);
/* The text of vn_io_format_g(out, v, digits) where a correctly rounding
 * reader (strtof: to nearest, ties to even) reads it back as v, and its
 * length; else 0 (out then holds no promise). Decided exactly in integers
 * where vn_io_format_g rounds in them and v is a normal float, by strtof
 * elsewhere. */
size_t vn_io_format_float(char* out, float v, int digits);

/* The longest number token the readers take; longer ones are an error
 * rather than cut short. */
#define VN_IO_TOKEN_MAX 255

/* The n bytes at p, all of them, as a number (strtod: "nan" and "inf" too);
 * 0 when they are not one or are longer than VN_IO_TOKEN_MAX. Call it in
 * the C locale (vn_io_c_locale_enter). */
int vn_io_parse_real(const unsigned char* p, size_t n, double* out);

/* Input text fit for a message: at most 24 characters, unprintable bytes as
 * '?' (the input may be any binary garbage). Used as
 * vn_io_quote(p, n).text within one expression. */
typedef struct vn_io_quoted {
	char text[32];
} vn_io_quoted;
vn_io_quoted vn_io_quote(const unsigned char* p, size_t n);

/* Appends printf's text of fmt as one more line of *lines ("\n"-separated,
 * NULL when empty: a reader's warnings); 0 when out of memory (*lines
 * unchanged). */
int vn_io_append_line(char** lines, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* The length of a UTF-8 byte order mark at the n bytes at p (3), or 0: the
 * text formats read past one (Windows editors write it). */
size_t vn_io_utf8_bom(const unsigned char* p, size_t n);
/* The encoding a UTF-16 or UTF-32 byte order mark at p names ("UTF-16LE"
 * ...), or NULL. */
const char* vn_io_wide_bom(const unsigned char* p, size_t n);
/* The n bytes at p, text in the UTF-16 or UTF-32 whose byte order mark
 * starts them (vn_io_wide_bom), as UTF-8 without the mark: *out (malloc'd,
 * NUL-terminated, the caller frees it) of *out_size bytes. Text formats are
 * read through it: Windows PowerShell's '>' writes UTF-16LE, and so do
 * scripts run under it. Line breaks stay where they were, so the reader's
 * line numbers are the file's. Fails (vn_io_error_parse, naming `name` and
 * the line) at an odd byte at the end, a surrogate without its pair or a
 * value beyond U+10FFFF; vn_io_error_memory when out of memory. */
vn_io_result vn_io_utf8_from_wide(const unsigned char* p, size_t n, const char* name, char** out, size_t* out_size,
                                  vn_io_error* error);
/* A text format's reader of the size bytes at data (name in messages):
 * `wide` names the encoding they were decoded from, or is NULL. */
typedef vn_io_result (*vn_io_text_reader)(const char* data, size_t size, const char* name, const char* wide,
                                          vn_io_mesh* mesh, vn_io_error* error);
/* read on the size bytes at data (NULL: none), decoded to UTF-8 first where
 * they start with a UTF-16 or UTF-32 byte order mark (vn_io_utf8_from_wide;
 * mesh zeroed when that fails). */
vn_io_result vn_io_read_text(const char* data, size_t size, const char* name, vn_io_text_reader read,
                             vn_io_mesh* mesh, vn_io_error* error);
/* Fails (vn_io_error_parse, naming `name`) when the n bytes at p are a Git
 * LFS pointer ("version https://git-lfs.github.com/spec/v1", oid, size): a
 * repository cloned without its large files, which every reader would
 * otherwise call malformed or, as an OBJ of no known line, read as empty.
 * vn_io_success otherwise. */
vn_io_result vn_io_refuse_lfs_pointer(const void* p, size_t n, const char* name, vn_io_error* error);

/* A reader's error at a place in the file: "name:where: what" (a line), or
 * "name: byte where: what" when `byte`; what is fmt with args. Returns r. */
vn_io_result vn_io_fail_at(vn_io_error* error, vn_io_result r, const char* name, int byte, size_t where,
                           const char* fmt, va_list args);

#endif /* VN_IO_TEXT_H */
