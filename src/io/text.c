/* Numbers as text for the text formats: see text.h. */
#define _POSIX_C_SOURCE 200809L /* newlocale, uselocale */

#include "text.h"

#include <errno.h>
#include <locale.h>
#include <stdlib.h>
#include <string.h>

int vn_io_c_locale_enter(vn_io_c_locale* l)
{
	locale_t c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
	if (!c)
		return 0;
	l->c = c;
	l->previous = uselocale(c);
	return 1;
}

void vn_io_c_locale_leave(vn_io_c_locale* l)
{
	uselocale((locale_t)l->previous);
	freelocale((locale_t)l->c);
}

void vn_io_put(vn_io_text_out* w, const char* text)
{
	if (!w->failed && fputs(text, w->out) == EOF) {
		w->failed = 1;
		w->error_number = errno;
	}
}

void vn_io_put_float9(vn_io_text_out* w, double v)
{
	char text[40];
	snprintf(text, sizeof text, " %.9g", v);
	vn_io_put(w, text);
}

void vn_io_put_float(vn_io_text_out* w, float v)
{
	char text[40];
	for (int digits = 6;; digits++) {
		snprintf(text, sizeof text, " %.*g", digits, (double)v);
		if (digits == 9 || (float)strtod(text, NULL) == v)
			break;
	}
	vn_io_put(w, text);
}

void vn_io_put_exact(vn_io_text_out* w, const char* separator, double v)
{
	char text[40];
	for (int digits = 15;; digits++) {
		snprintf(text, sizeof text, "%s%.*g", separator, digits, v);
		if (digits == 17 || strtod(text, NULL) == v)
			break;
	}
	vn_io_put(w, text);
}

int vn_io_parse_real(const unsigned char* p, size_t n, double* out)
{
	char text[VN_IO_TOKEN_MAX + 1];
	char* stop;
	if (n == 0 || n > VN_IO_TOKEN_MAX)
		return 0;
	memcpy(text, p, n);
	text[n] = '\0';
	*out = strtod(text, &stop);
	return stop == text + n;
}

int vn_io_append_line(char** lines, const char* text)
{
	const size_t used = *lines ? strlen(*lines) : 0, n = strlen(text);
	char* grown = realloc(*lines, used + n + 2);
	if (!grown)
		return 0;
	*lines = grown;
	snprintf(grown + used, n + 2, "%s%s", used ? "\n" : "", text);
	return 1;
}

size_t vn_io_utf8_bom(const unsigned char* p, size_t n)
{
	return n >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

const char* vn_io_wide_bom(const unsigned char* p, size_t n)
{
	if (n >= 4 && memcmp(p, "\xFF\xFE\0\0", 4) == 0)
		return "UTF-32LE";
	if (n >= 4 && memcmp(p, "\0\0\xFE\xFF", 4) == 0)
		return "UTF-32BE";
	if (n >= 2 && memcmp(p, "\xFF\xFE", 2) == 0)
		return "UTF-16LE";
	if (n >= 2 && memcmp(p, "\xFE\xFF", 2) == 0)
		return "UTF-16BE";
	return NULL;
}

vn_io_quoted vn_io_quote(const unsigned char* p, size_t n)
{
	vn_io_quoted q;
	const size_t k = n > 24 ? 24 : n;
	for (size_t i = 0; i < k; i++)
		q.text[i] = p[i] >= 0x20 && p[i] < 0x7f ? (char)p[i] : '?';
	strcpy(q.text + k, n > k ? "..." : "");
	return q;
}

vn_io_result vn_io_fail_at(vn_io_error* error, vn_io_result r, const char* name, int byte, size_t where,
                           const char* fmt, va_list args)
{
	char what[384];
	vsnprintf(what, sizeof what, fmt, args);
	if (byte)
		return vn_io_fail(error, r, "%s: byte %zu: %s", name, where, what);
	return vn_io_fail(error, r, "%s:%zu: %s", name, where, what);
}
