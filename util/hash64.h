/* 64-bit FNV-1a (Fowler–Noll–Vo): the content hash of atmospheres, cached
 * tables, cached fits and training runs, and the checksum of table files.
 * Not cryptographic; chosen because it is tiny, portable and exact to
 * reproduce. Each step h = (h ^ byte) * prime is a
 * bijection of the state, so two messages of equal length that differ in
 * one byte never collide — every single-byte corruption of a checksummed
 * table file is caught. */
#ifndef SKYFIT_UTIL_HASH64_H
#define SKYFIT_UTIL_HASH64_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define SF_FNV1A64_OFFSET 0xcbf29ce484222325ull
#define SF_FNV1A64_PRIME 0x100000001b3ull

static inline uint64_t sf_fnv1a64(uint64_t h, const void *bytes, size_t n) {
  const unsigned char *p = (const unsigned char *)bytes;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * SF_FNV1A64_PRIME;
  return h;
}

/* Feeds the length (8 bytes, little-endian) and then the bytes of s, so
 * that consecutive fields cannot trade characters ("ab","c" vs "a","bc"). */
static inline uint64_t sf_fnv1a64_field(uint64_t h, const char *s) {
  size_t n = strlen(s);
  unsigned char len[8];
  for (int i = 0; i < 8; ++i) len[i] = (unsigned char)((uint64_t)n >> (8 * i));
  return sf_fnv1a64(sf_fnv1a64(h, len, 8), s, n);
}

/* MurmurHash3's 64-bit finaliser: a bijection that spreads every input bit
 * over the whole word, so keys that differ only in their last field do not
 * look alike (plain FNV-1a changes few bits for a change in the last byte). */
static inline uint64_t sf_hash64_mix(uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

/* 16 lowercase hex digits and a NUL. */
static inline void sf_hash64_hex(uint64_t h, char out[17]) {
  snprintf(out, 17, "%016llx", (unsigned long long)h);
}

#endif
