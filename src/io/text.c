/* Numbers as text for the text formats: see text.h. */
#define _POSIX_C_SOURCE 200809L /* newlocale, uselocale */

#include "text.h"

#include <errno.h>
#include <float.h>
#include <locale.h>
#include <math.h>
#include <stdint.h>
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

/* Writes the buffer's bytes, unless an earlier write failed. */
static void drain(vn_io_text_out* w)
{
	if (!w->failed && w->used && fwrite(w->buffer, 1, w->used, w->out) != w->used) {
		w->failed = 1;
		w->error_number = errno;
	}
	w->used = 0;
}

/* The n bytes at text. */
static void put_bytes(vn_io_text_out* w, const char* text, size_t n)
{
	while (n > sizeof w->buffer - w->used) {
		const size_t room = sizeof w->buffer - w->used;
		memcpy(w->buffer + w->used, text, room);
		w->used += room, text += room, n -= room;
		drain(w);
	}
	memcpy(w->buffer + w->used, text, n);
	w->used += n;
}

void vn_io_put(vn_io_text_out* w, const char* text)
{
	put_bytes(w, text, strlen(text));
}

void vn_io_put_comments(vn_io_text_out* w, const char* comments, const char* prefix)
{
	while (comments) {
		const size_t n = strcspn(comments, "\n");
		vn_io_put(w, prefix);
		put_bytes(w, comments, n);
		vn_io_put(w, "\n");
		comments = comments[n] ? comments + n + 1 : NULL;
	}
}

/* Byte by byte into the buffer: a call to memcpy a number cost as much as
 * its digits. */
void vn_io_put_uint(vn_io_text_out* w, const char* before, uint64_t v)
{
	for (const char* c = before; *c; c++) {
		if (w->used == sizeof w->buffer)
			drain(w);
		w->buffer[w->used++] = *c;
	}
	size_t n = 1; /* digits */
	for (uint64_t rest = v; rest >= 10; rest /= 10)
		n++;
	if (n > sizeof w->buffer - w->used)
		drain(w);
	for (size_t k = n; k-- > 0; v /= 10)
		w->buffer[w->used + k] = (char)('0' + v % 10);
	w->used += n;
}

int vn_io_flush(vn_io_text_out* w)
{
	drain(w);
	return !w->failed;
}

void vn_io_put_float9(vn_io_text_out* w, double v)
{
	char text[VN_IO_NUMBER_SIZE + 1] = " ";
	vn_io_format_g(text + 1, v, 9);
	vn_io_put(w, text);
}

void vn_io_put_float(vn_io_text_out* w, float v)
{
	char text[VN_IO_NUMBER_SIZE + 1] = " ";
	int digits = 6;
	while (digits < 9 && !vn_io_format_float(text + 1, v, digits))
		digits++;
	if (digits == 9) /* 9 digits read back as any float */
		vn_io_format_g(text + 1, (double)v, 9);
	vn_io_put(w, text);
}

void vn_io_put_exact(vn_io_text_out* w, int space, double v)
{
	char text[VN_IO_NUMBER_SIZE + 1] = " ";
	vn_io_format_exact(text + (space != 0), v);
	vn_io_put(w, text);
}

/* ---------------------------------------------------------------- %g */

#ifdef __SIZEOF_INT128__
__extension__ typedef unsigned __int128 vn_u128;

static const uint64_t POWER_OF_10[18] = {
	1ull, 10ull, 100ull, 1000ull,
	10000ull, 100000ull, 1000000ull, 10000000ull,
	100000000ull, 1000000000ull, 10000000000ull, 100000000000ull,
	1000000000000ull, 10000000000000ull, 100000000000000ull, 1000000000000000ull,
	10000000000000000ull, 100000000000000000ull,
};

static const uint64_t POWER_OF_5[28] = {
	1ull, 5ull, 25ull, 125ull,
	625ull, 3125ull, 15625ull, 78125ull,
	390625ull, 1953125ull, 9765625ull, 48828125ull,
	244140625ull, 1220703125ull, 6103515625ull, 30517578125ull,
	152587890625ull, 762939453125ull, 3814697265625ull, 19073486328125ull,
	95367431640625ull, 476837158203125ull, 2384185791015625ull, 11920928955078125ull,
	59604644775390625ull, 298023223876953125ull, 1490116119384765625ull, 7450580596923828125ull,
};

/* a (finite, > 0) as m 2^e, m its 53-bit significand; 0 for a subnormal. */
static int split(double a, uint64_t* m, int* e)
{
	uint64_t bits;
	memcpy(&bits, &a, sizeof bits);
	const int biased = (int)(bits >> 52);
	*m = (bits & (((uint64_t)1 << 52) - 1)) | (uint64_t)1 << 52;
	*e = biased - 1075;
	return biased != 0;
}

/* a's p significant digits (1 <= p <= 17) as printf makes them, rounded to
 * nearest, ties to even, from the exact binary value: a = q 10^(x - p + 1)
 * with q in [10^(p - 1), 10^p), q exact in integers, and a 10^(p - 1 - x)
 * = M / 2^sh exactly. */
typedef struct digits {
	uint64_t q, m;
	int x, sh;
	vn_u128 M;
} digits;

/* The digits where M = m 5^s fits (s = p - 1 - x in [0, 27]: 5^27 < 2^63)
 * and sh is in [1, 69], which the rounding and reads_back need; 0
 * elsewhere (a far from 1: the callers use the C library). x is
 * floor(log10 a) or one less. */
static int round_digits(double a, int p, int x, digits* d)
{
	uint64_t m;
	int e;
	if (!split(a, &m, &e))
		return 0;
	/* q >= 10^p: x is one too small, or a's digits round up to 10^p; either
	 * way x + 1. q = 10^(p - 1): a is at or above 10^x, or below it and
	 * rounded up; x - 1 tells them apart (there, digits below 10^p are
	 * a's). */
	for (int tries = 0, below = 0; tries < 4; ++tries) {
		const int s = p - 1 - x, sh = -e - s; /* a 10^s = m 5^s 2^(e + s) */
		if (s < 0 || s > 27 || sh < 1 || sh > 69)
			return 0;
		const vn_u128 M = (vn_u128)m * POWER_OF_5[s], whole = M >> sh;
		const vn_u128 half = (vn_u128)1 << (sh - 1), r = M & ((half << 1) - 1);
		const vn_u128 q = whole + (r > half || (r == half && (whole & 1)));
		if (q >= POWER_OF_10[p] && !below) {
			++x;
			continue;
		}
		if (q < POWER_OF_10[p] && (q > POWER_OF_10[p - 1] || below)) {
			d->q = (uint64_t)q, d->m = m, d->x = x, d->sh = sh, d->M = M;
			return 1;
		}
		if (below) /* x - 1 rounds up to 10^p: x's 10^(p - 1) stands */
			return 1;
		if (q == POWER_OF_10[p - 1])
			d->q = (uint64_t)q, d->m = m, d->x = x, d->sh = sh, d->M = M, below = 1;
		--x;
	}
	return 0;
}

/* floor(log10 a) or one less, from a's binary exponent: a in [2^k, 2^(k + 1)). */
static int decimal_exponent(double a)
{
	uint64_t m;
	int e;
	split(a, &m, &e);
	return (int)floor((e + 52) * 0.30102999566398120);
}

/* Whether q 10^(x - p + 1) reads back as a, as a double (shift 0: strtod)
 * or, where a is a normal float's value, as a float (shift 29: strtof; a
 * float's ulp is 2^29 of the double's, its significand the double's top 24
 * bits); both round to nearest: q is nearer to a than half the gap to a's
 * neighbour on its side. In units of 2^-(sh + 1) 10^-s (s = p - 1 - x):
 * |q - a 10^s| against half an ulp, 5^s 2^shift (a 10^s = M / 2^sh, a
 * double's ulp(a) 10^s = 5^s / 2^sh); against a quarter below a power of 2,
 * whose lower neighbour is half an ulp away. No tie is possible here. For
 * doubles: a midpoint between two doubles whose lowest bit is 2^-1 or finer
 * (sh >= 1) is an odd multiple of a power of 2 of at least 54 bits and
 * needs more than 17 digits. For floats, where round_digits holds (s >= 0):
 * a float's ulp there is finer than the decimal grid 10^-s or a float is on
 * the grid, and a point halfway between floats has one binary place more
 * than their ulp, so more decimal places than the grid. (Float ties exist
 * above 2^24: 33554450 is halfway between 33554448 and 33554452; strtof
 * decides those.) */
static int reads_back(const digits* d, int p, int shift)
{
	const vn_u128 at = (vn_u128)d->q << (d->sh + 1), twice = d->M << 1; /* q < 2^57, sh + 1 <= 70 */
	const vn_u128 diff = at > twice ? at - twice : twice - at;
	const vn_u128 half = (vn_u128)POWER_OF_5[p - 1 - d->x] << shift;
	if (at < twice && d->m == (uint64_t)1 << 52)
		return 2 * diff < half;
	return diff < half;
}

/* printf's "%.*g" text of the digits: exponent style where x < -4 or x >=
 * p, trailing zeros of the fraction (and a bare point) dropped. */
static size_t format_digits(char* out, int negative, const digits* d, int p)
{
	char s[17];
	uint64_t q = d->q;
	for (int i = p - 1; i >= 0; --i)
		s[i] = (char)('0' + q % 10), q /= 10;
	const int x = d->x, point = x < -4 || x >= p ? 1 : x >= 0 ? x + 1 : 0; /* digits before the point */
	int k = p;
	while (k > point && k > 1 && s[k - 1] == '0')
		--k;
	char* o = out;
	if (negative)
		*o++ = '-';
	if (x < 0 && x >= -4) { /* 0.000ddd */
		*o++ = '0', *o++ = '.';
		for (int i = 0; i < -x - 1; ++i)
			*o++ = '0';
		memcpy(o, s, (size_t)k), o += k;
	} else {
		memcpy(o, s, (size_t)point), o += point;
		if (k > point)
			*o++ = '.', memcpy(o, s + point, (size_t)(k - point)), o += k - point;
		if (point == 1 && (x < -4 || x >= p)) {
			const int e = x < 0 ? -x : x;
			*o++ = 'e', *o++ = x < 0 ? '-' : '+';
			if (e >= 100)
				*o++ = (char)('0' + e / 100);
			*o++ = (char)('0' + e / 10 % 10), *o++ = (char)('0' + e % 10);
		}
	}
	*o = '\0';
	return (size_t)(o - out);
}
#endif

size_t vn_io_format_g(char* out, double v, int p)
{
#ifdef __SIZEOF_INT128__
	digits d;
	if (v == 0.0 && p >= 1 && p <= 17) {
		strcpy(out, signbit(v) ? "-0" : "0");
		return strlen(out);
	}
	if (isfinite(v) && p >= 1 && p <= 17 && round_digits(fabs(v), p, decimal_exponent(fabs(v)), &d))
		return format_digits(out, signbit(v) != 0, &d, p);
#endif
	return (size_t)snprintf(out, VN_IO_NUMBER_SIZE, "%.*g", p, v);
}

size_t vn_io_format_exact(char* out, double v)
{
#ifdef __SIZEOF_INT128__
	const int x = v != 0.0 && isfinite(v) ? decimal_exponent(fabs(v)) : 0;
#endif
	for (int p = 15;; p++) {
#ifdef __SIZEOF_INT128__
		digits d;
		if (v != 0.0 && isfinite(v) && round_digits(fabs(v), p, x, &d)) {
			if (p == 17 || reads_back(&d, p, 0))
				return format_digits(out, signbit(v) != 0, &d, p);
			continue;
		}
#endif
		const size_t n = vn_io_format_g(out, v, p);
		if (p == 17 || strtod(out, NULL) == v)
			return n;
	}
}

size_t vn_io_format_float(char* out, float v, int p)
{
	const double a = (double)v;
#ifdef __SIZEOF_INT128__
	digits d;
	if (isfinite(a) && fabs(a) >= FLT_MIN && p >= 1 && p <= 9 &&
	    round_digits(fabs(a), p, decimal_exponent(fabs(a)), &d))
		return reads_back(&d, p, 29) ? format_digits(out, signbit(a) != 0, &d, p) : 0;
#endif
	const size_t n = vn_io_format_g(out, a, p);
	return strtof(out, NULL) == v ? n : 0;
}

#ifdef __SIZEOF_INT128__
/* m / 10^f rounded to nearest, ties to even, for 0 < m < 10^19 and f <=
 * 22: m shifted to the top of 128 bits and divided in integers leaves a
 * quotient of 54 bits or more (10^22 < 2^74), rounded to 53 with the
 * remainder as the sticky bit. */
static double divide_exact(uint64_t m, int f)
{
	const vn_u128 ten = f <= 17 ? POWER_OF_10[f] : (vn_u128)POWER_OF_10[17] * POWER_OF_10[f - 17];
	const int s = 64 + __builtin_clzll(m);
	const vn_u128 w = (vn_u128)m << s, q = w / ten, r = w % ten;
	const uint64_t high = (uint64_t)(q >> 64);
	const int bits = high ? 128 - __builtin_clzll(high) : 64 - __builtin_clzll((uint64_t)q);
	int drop = bits - 53;
	uint64_t mantissa = (uint64_t)(q >> drop);
	const vn_u128 low = q & (((vn_u128)1 << drop) - 1), half = (vn_u128)1 << (drop - 1);
	if (low > half || (low == half && (r != 0 || (mantissa & 1))))
		mantissa++;
	if (mantissa >> 53) /* rounded up to 2^53: even, exact halved */
		mantissa >>= 1, drop++;
	return ldexp((double)mantissa, drop - s);
}
#endif

/* The numbers mesh files are made of, [-+]digits[.digits] with at most 22
 * digits after the point, without strtod's cost (a third of reading an
 * OBJ; its arbitrary precision, half of reading an OFF of 17 digits): up to
 * 15 significant digits by Clinger's exact fast path (their integer, below
 * 2^53, exact as a double, divided by a power of ten, exact up to 1e22: one
 * division rounds correctly), up to 19 by divide_exact; strtod's double
 * either way. 0 for any other spelling, which strtod reads. */
static int parse_decimal(const unsigned char* p, size_t n, double* out)
{
	static const double tens[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
	                                1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
	size_t i = n && (p[0] == '-' || p[0] == '+');
	uint64_t m = 0;
	int significant = 0, fraction = 0, point = 0, any = 0;
	for (; i < n; i++) {
		const unsigned d = (unsigned)p[i] - '0';
		if (p[i] == '.' && !point) {
			point = 1;
			continue;
		}
		if (d > 9)
			return 0;
		any = 1;
		fraction += point;
		if ((m || d) && ++significant > 19)
			return 0;
		m = 10 * m + d;
	}
	if (!any || fraction > 22)
		return 0;
#ifdef __SIZEOF_INT128__
	const double v = significant <= 15 ? (double)m / tens[fraction] : divide_exact(m, fraction);
#else
	if (significant > 15)
		return 0;
	const double v = (double)m / tens[fraction];
#endif
	*out = n && p[0] == '-' ? -v : v;
	return 1;
}

int vn_io_parse_real(const unsigned char* p, size_t n, double* out)
{
	if (parse_decimal(p, n, out))
		return 1;
	char text[VN_IO_TOKEN_MAX + 1];
	char* stop;
	if (n == 0 || n > VN_IO_TOKEN_MAX)
		return 0;
	memcpy(text, p, n);
	text[n] = '\0';
	*out = strtod(text, &stop);
	return stop == text + n;
}

int vn_io_append_line(char** lines, const char* fmt, ...)
{
	va_list args, again;
	va_start(args, fmt);
	va_copy(again, args);
	const int n = vsnprintf(NULL, 0, fmt, args);
	va_end(args);
	size_t used = *lines ? strlen(*lines) : 0;
	char* grown = n < 0 ? NULL : realloc(*lines, used + (size_t)n + 2);
	if (grown) {
		*lines = grown;
		if (used)
			grown[used++] = '\n';
		vsnprintf(grown + used, (size_t)n + 1, fmt, again);
	}
	va_end(again);
	return grown != NULL;
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

/* One code unit of `size` bytes at p, in the given byte order. */
static uint32_t code_unit(const unsigned char* p, size_t size, int big)
{
	uint32_t u = 0;
	for (size_t i = 0; i < size; i++)
		u |= (uint32_t)p[big ? i : size - 1 - i] << 8 * (size - 1 - i);
	return u;
}

vn_io_result vn_io_utf8_from_wide(const unsigned char* p, size_t n, const char* name, char** out, size_t* out_size,
                                  vn_io_error* error)
{
	const char* wide = vn_io_wide_bom(p, n);
	const size_t size = wide[4] == '3' ? 4 : 2; /* "UTF-32..." or "UTF-16..." */
	const int big = wide[6] == 'B';
	/* A unit of 2 bytes becomes at most 3 (a pair of 4, 4); one of 4, 4. */
	char* s = (char*)malloc(n / 2 * 3 + 1);
	if (!s)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	size_t k = 0, line = 1;
	const char* bad = NULL;
	for (size_t i = size; i < n && !bad; i += size) {
		if (n - i < size) {
			bad = "its last code unit is cut short";
			break;
		}
		uint32_t c = code_unit(p + i, size, big);
		if (size == 2 && c >= 0xD800 && c <= 0xDBFF) { /* a high surrogate, then its low one */
			const uint32_t low = n - i >= 4 ? code_unit(p + i + 2, 2, big) : 0;
			if (low < 0xDC00 || low > 0xDFFF) {
				bad = "a high surrogate without its low one";
				break;
			}
			c = 0x10000 + ((c - 0xD800) << 10) + (low - 0xDC00);
			i += 2;
		} else if (c >= 0xD800 && c <= 0xDFFF) {
			bad = "a low surrogate without its high one";
			break;
		} else if (c > 0x10FFFF) {
			bad = "a value beyond U+10FFFF";
			break;
		}
		if (c < 0x80) {
			s[k++] = (char)c;
			line += c == '\n';
		} else if (c < 0x800) {
			s[k++] = (char)(0xC0 | c >> 6);
			s[k++] = (char)(0x80 | (c & 0x3F));
		} else if (c < 0x10000) {
			s[k++] = (char)(0xE0 | c >> 12);
			s[k++] = (char)(0x80 | (c >> 6 & 0x3F));
			s[k++] = (char)(0x80 | (c & 0x3F));
		} else {
			s[k++] = (char)(0xF0 | c >> 18);
			s[k++] = (char)(0x80 | (c >> 12 & 0x3F));
			s[k++] = (char)(0x80 | (c >> 6 & 0x3F));
			s[k++] = (char)(0x80 | (c & 0x3F));
		}
	}
	if (bad) {
		free(s);
		return vn_io_fail(error, vn_io_error_parse, "%s:%zu: the text is %s (it starts with a byte order mark), but %s",
		                  name, line, wide, bad);
	}
	s[k] = '\0';
	*out = s;
	*out_size = k;
	return vn_io_success;
}

vn_io_result vn_io_read_text(const char* data, size_t size, const char* name, vn_io_text_reader read,
                             vn_io_mesh* mesh, vn_io_error* error)
{
	const char* wide = data ? vn_io_wide_bom((const unsigned char*)data, size) : NULL;
	if (!wide)
		return read(data, size, name, NULL, mesh, error);
	memset(mesh, 0, sizeof *mesh);
	char* utf8 = NULL;
	size_t n;
	vn_io_result r = vn_io_utf8_from_wide((const unsigned char*)data, size, name, &utf8, &n, error);
	if (r == vn_io_success)
		r = read(utf8, n, name, wide, mesh, error);
	free(utf8);
	return r;
}

vn_io_result vn_io_refuse_lfs_pointer(const void* p, size_t n, const char* name, vn_io_error* error)
{
	static const char version[] = "version https://git-lfs.github.com/spec/";
	const char* text = (const char*)p;
	/* The specification keeps pointers under 1024 bytes. */
	if (n >= 1024 || n < sizeof version - 1 || memcmp(text, version, sizeof version - 1) != 0)
		return vn_io_success;
	unsigned long long bytes = 0;
	int known = 0;
	for (size_t i = 0; i + 5 < n && !known; i++)
		if (text[i] == '\n' && memcmp(text + i + 1, "size ", 5) == 0) {
			char line[32] = {0};
			memcpy(line, text + i + 6, n - i - 6 < sizeof line - 1 ? n - i - 6 : sizeof line - 1);
			known = sscanf(line, "%llu", &bytes) == 1;
		}
	char size[48] = "";
	if (known)
		snprintf(size, sizeof size, " (whose %llu bytes are in LFS storage)", bytes);
	return vn_io_fail(error, vn_io_error_parse,
	                  "%s: a Git LFS pointer, not the file itself%s: fetch it with 'git lfs pull'", name, size);
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
