/* The reference tables of one atmosphere (SPEC §6), computed or taken from
 * the cache: transmittance, one single-scattering table per scattering
 * constituent ("single_<name>"), multiple scattering ("multiple", all
 * orders >= 2 summed) and Bruneton's indirect ground irradiance
 * ("irradiance"), in one parameterisation and resolution.
 *
 * With a cache folder, each table is DIR/<quantity>-<key>.exr
 * (data/table_cache.h), the key hashing the atmosphere's canonical JSON,
 * the table's description (quantity, parameterisation, axes, channels), the
 * number of orders and SF_TABLES_CODE_VERSION. A cached table is loaded, not
 * recomputed; a corrupt one is reported (through note) and recomputed over. */
#ifndef SKYFIT_DATA_TABLE_SET_H
#define SKYFIT_DATA_TABLE_SET_H

#include <stddef.h>
#include <stdint.h>

#include "data/precompute_multiple.h"
#include "data/precompute_options.h"
#include "data/sample_memo.h"
#include "data/table.h"
#include "data/table_params.h"
#include "models/atmosphere.h"
#include "util/error.h"

/* Bump whenever a change makes the tables' values differ, or what a table
 * file holds (4: the multiple table's skyfit:orders, data/table_exr.h,
 * which tables cached before lack). */
#define SF_TABLES_CODE_VERSION "skyfit-tables 10"   /* 10: G's ground half linear in mu, data/density_mu.h */
/* All orders (SPEC §6): up to the most, stopping once the orders left
 * would add less than 5e-4 of every channel's sky radiance (estimated as
 * the geometric tail of the last two; 7 orders for the built-in Earth,
 * whose orders shrink by about 0.3 each; a fixed 4 had left the blue
 * multiple scattering 4-5 % short of the path tracer's). A sky whose
 * orders shrink slowly (thick, bright) may reach the most first: the set
 * then says what is left (sf_table_set_options.note). With a stop
 * fraction the orders after the last are added as that geometric tail
 * (data/precompute_multiple.c); without one the tables hold exactly the
 * orders asked for. */
#define SF_TABLE_SET_DEFAULT_ORDERS SF_MULTIPLE_MAX_ORDERS
#define SF_TABLE_SET_DEFAULT_STOP_FRACTION 5e-4

typedef struct sf_table_set_options {
  sf_parameterization kind;
  sf_table_resolution res;
  int orders;               /* highest scattering order, >= 1 */
  double stop_fraction;     /* see sf_multiple_options; 0: none */
  const char *cache_dir;    /* NULL: compute in memory, store nothing */
  /* A scene's domain (SPEC §5): with has_domain the scattering tables cover
   * only it (sf_table_params_restrict); their axes say so and the cache key
   * includes it through them. */
  int has_domain;
  sf_table_domain domain;
  int transmittance_only;   /* 1: only the transmittance table (a scene that
                               asks for transmittance alone) */
  sf_precompute_options run;
  void (*note)(void *ctx, const char *message);   /* may be NULL */
  void *note_ctx;
  /* A cached table that could not be used (damaged; recomputed): said
   * here when set, else through note. A build's notes are its report's,
   * which say nothing of where a table came from; this is the run's news. */
  void (*problem)(void *ctx, const char *message);
  void *problem_ctx;
} sf_table_set_options;

/* kind bruneton, default resolution, 4 orders, no stop, no cache, the full
 * domain, every table. */
void sf_table_set_options_default(sf_table_set_options *o);

enum { SF_TABLE_SET_MAX_TABLES = SF_MAX_CONSTITUENTS + 3 };

typedef struct sf_table_set {
  sf_table_params params;
  sf_table transmittance;
  int n_single;
  int single_constituent[SF_MAX_CONSTITUENTS];   /* atmosphere index of each */
  sf_table single[SF_MAX_CONSTITUENTS];
  sf_table multiple;
  sf_table irradiance;
  /* Every table in a fixed order (transmittance, singles, multiple,
   * irradiance; transmittance alone with transmittance_only), whether it
   * came from the cache, and its file (cache only). */
  int n_tables;
  sf_table *tables[SF_TABLE_SET_MAX_TABLES];
  int from_cache[SF_TABLE_SET_MAX_TABLES];
  char paths[SF_TABLE_SET_MAX_TABLES][4096];
  sf_multiple_report report;     /* when multiple scattering was computed */
  int multiple_computed;
  /* The sunlit air F (data/sunlit_ray.h) of every single table at its
   * samples, per constituent then channel, filled as lookups ask for it
   * (data/sky_lookup.c): owned; NULL without single tables (a set made by
   * hand may also leave it NULL: F is then computed at every lookup). */
  sf_sample_memo *single_sunlit;
  /* sf_atmosphere_hash of the atmosphere the tables are of: a view of
   * another atmosphere (data/sky_lookup.h) does not share single_sunlit */
  uint64_t atmosphere_hash;
} sf_table_set;

/* Bytes of memory the computation needs for these options (an estimate
 * that errs high), for rejecting absurd resolutions before any work. */
size_t sf_table_set_memory_bytes(const sf_atmosphere *atm, const sf_table_set_options *o);

/* Checks the options (resolution, orders, constituent names, domain, memory):
 * SF_ERR_INPUT with a message otherwise. Does nothing else. The memory the
 * tables need must fit in what the machine allows this process now
 * (util/memory_limit.h: available RAM, cgroup limit, ulimit -v / -d); the
 * message states the need, the limit and where the limit comes from. */
int sf_table_set_check(const sf_atmosphere *atm, const sf_table_set_options *o, sf_error *err);

/* Loads or computes every table. On failure set is empty (safe to free). */
int sf_table_set_make(sf_table_set *set, const sf_atmosphere *atm, const sf_table_set_options *o,
                      sf_error *err);
void sf_table_set_free(sf_table_set *set);

/* Whether the multiple scattering just computed ran out of orders (o's
 * most) before the orders left fell below o's stop fraction; if so, says
 * what the tables lack in text (at most n bytes). Tables from the cache
 * say the same: the multiple table keeps its orders (data/table.h). */
int sf_table_set_orders_short(const sf_table_set *set, const sf_table_set_options *o, char *text, size_t n);

#endif
