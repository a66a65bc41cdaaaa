/* Training (fit/train.h, fit/adam.h): Adam's first steps against the closed
 * form of Kingma & Ba's Algorithm 1; byte-identical networks for 1 and 2
 * threads (a full batch of 300,000 too, in larger chunks); an interrupted
 * run resumed from its checkpoint ends byte-identical to an uninterrupted
 * one; a teacher network's data are learnt (loss drops
 * by >= 100x); restarts keep the best validation loss, and restart r is
 * the same network trained in any call (first_restart). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fit/adam.h"
#include "fit/train.h"
#include "models/rng.h"
#include "tests/check.h"

/* Data from a fixed "teacher" 2-4-3 network plus a smooth extra term. */
static void make_data(sf_dataset *d, long n) {
  sf_error err = {0};
  sf_dataset_init(d, n, 2, 3, &err);
  sf_rng rng;
  sf_rng_seed(&rng, 99, 1, 2);
  for (long i = 0; i < n; ++i) {
    double a = 2.0 * sf_rng_uniform(&rng) - 1.0, b = 2.0 * sf_rng_uniform(&rng) - 1.0;
    d->x[2 * i] = a;
    d->x[2 * i + 1] = b;
    for (int c = 0; c < 3; ++c) d->y[3 * i + c] = exp(-(0.5 + 0.3 * c) * (1.2 + a + 0.5 * b * b));
  }
}

static int run(const sf_dataset *tr, const sf_dataset *va, sf_train_options *o, sf_train_result *r) {
  sf_error err = {0};
  int s = sf_mlp_train(tr, va, o, r, &err);
  if (s) printf("train failed: %s\n", err.message);
  return s;
}

/* Progress callback: the first epoch's training loss into *ctx. */
static void first_epoch_loss(void *ctx, int restart, int n_restarts, int epoch, int n_epochs, double train_loss,
                             double validation_loss) {
  (void)restart, (void)n_restarts, (void)n_epochs, (void)validation_loss;
  if (epoch == 1) *(double *)ctx = train_loss;
}

int main(void) {
  /* Adam, closed form of the first two steps on g = const: m_hat = g,
   * v_hat = g^2, so each step moves by lr * g / (|g| + eps). */
  sf_adam adam;
  sf_adam_options ao;
  sf_adam_options_default(&ao);
  sf_adam_init(&adam, 2);
  double theta[2] = {1.0, -2.0}, g[2] = {0.5, -3e-3};
  sf_adam_step(&adam, &ao, ao.lr, theta, g);
  CHECK_REL(theta[0], 1.0 - 0.01 * 0.5 / (0.5 + 1e-8), 1e-15);
  CHECK_REL(theta[1], -2.0 + 0.01 * 3e-3 / (3e-3 + 1e-8), 1e-15);
  sf_adam_step(&adam, &ao, ao.lr, theta, g);
  CHECK_REL(theta[0], 1.0 - 2.0 * 0.01 * 0.5 / (0.5 + 1e-8), 1e-14);
  /* A gradient that changes sign: m = 0.9*0.1*g1 + 0.1*g2 etc., by hand. */
  sf_adam_free(&adam);
  sf_adam_init(&adam, 1);
  double th = 0.0, g1 = 1.0, g2 = -2.0;
  sf_adam_step(&adam, &ao, ao.lr, &th, &g1);
  double m1 = 0.1 * g1, v1 = 0.001 * g1 * g1;
  double m2 = 0.9 * m1 + 0.1 * g2, v2 = 0.999 * v1 + 0.001 * g2 * g2;
  double want = -0.01 * (m1 / 0.1) / (sqrt(v1 / 0.001) + 1e-8);
  want -= 0.01 * (m2 / (1 - 0.81)) / (sqrt(v2 / (1 - 0.999 * 0.999)) + 1e-8);
  sf_adam_step(&adam, &ao, ao.lr, &th, &g2);
  CHECK_REL(th, want, 1e-13);
  CHECK_REL(sf_adam_lr(&(sf_adam_options){0.01, 0.9, 0.999, 1e-8, 0.5}, 3), 0.01 * 0.125, 1e-15);
  sf_adam_free(&adam);

  /* 37 parameters (vector lanes and a tail on every instruction set of
   * fit/adam.c), 3 steps: bit for bit Algorithm 1 written out per parameter. */
  enum { NP = 37 };
  sf_adam_init(&adam, NP);
  double th37[NP], ref[NP], m_ref[NP] = {0}, v_ref[NP] = {0}, g37[NP];
  for (int k = 0; k < NP; ++k) th37[k] = ref[k] = 0.1 * k - 1.7;
  int same_bits = 1;
  for (int step = 1; step <= 3; ++step) {
    for (int k = 0; k < NP; ++k) g37[k] = sin(1.3 * k + step) * pow(10.0, (double)(k % 5) - 3.0);
    sf_adam_step(&adam, &ao, ao.lr, th37, g37);
    double c1 = 1.0 - pow(0.9, step), c2 = 1.0 - pow(0.999, step);
    for (int k = 0; k < NP; ++k) {
      m_ref[k] = 0.9 * m_ref[k] + (1.0 - 0.9) * g37[k];
      v_ref[k] = 0.999 * v_ref[k] + (1.0 - 0.999) * g37[k] * g37[k];
      ref[k] -= 0.01 * (m_ref[k] / c1) / (sqrt(v_ref[k] / c2) + 1e-8);
    }
    same_bits &= memcmp(th37, ref, sizeof th37) == 0;
  }
  CHECK(same_bits);
  sf_adam_free(&adam);

  sf_dataset all, tr, va;
  make_data(&all, 3000);
  sf_error err = {0};
  sf_dataset_split(&all, 0.2, 5, &tr, &va, &err);
  CHECK(tr.n == 2400 && va.n == 600);

  sf_train_options o;
  sf_train_options_default(&o);
  sf_mlp_shape_parse_layers("2,6,3", &o.shape, &err);
  o.shape.hidden = SF_ACT_TANH;
  o.shape.output = SF_ACT_EXP_NEG;
  o.epochs = 12;
  o.batch = 300;   /* several chunks per batch: the threads split them */
  o.parallel_work = 0.0;   /* even a batch this small */
  o.restarts = 2;
  o.patience = 4;
  o.seed = 7;

  /* Zeroed: a result's network is owned (and freed here) even when a run
   * fails before making it. An interrupted run's network is owned too. */
  sf_train_result r1 = {0}, r2 = {0}, r3 = {0}, r4 = {0};
  o.n_threads = 1;
  run(&tr, &va, &o, &r1);
  o.n_threads = 2;
  run(&tr, &va, &o, &r2);
  int np = r1.net.n_params;
  int same_threads = memcmp(r1.net.params, r2.net.params, (size_t)np * sizeof(double)) == 0;
  printf("1 vs 2 threads: validation loss %.17g vs %.17g, weights identical: %d\n", r1.validation_loss,
         r2.validation_loss, same_threads);
  CHECK(same_threads);

  /* Restart r is the same network whichever call trains it: restarts 0
   * and 1 trained one per call (first_restart) give the two-restart run's
   * kept network, the one of lower validation loss, bit for bit. Seed 8
   * is one whose restart 1 wins (found by trying 8-14: 8 and 11), so that
   * restart 1's own call is compared with the network kept. */
  {
    const uint64_t seed_r1 = 8;
    sf_train_result both = {0}, ra = {0}, rb = {0}, rc = {0};
    sf_train_options two = o, one = o;
    two.seed = one.seed = seed_r1;
    run(&tr, &va, &two, &both);
    one.restarts = 1;
    run(&tr, &va, &one, &ra);
    one.first_restart = 1;
    run(&tr, &va, &one, &rb);
    printf("seed %d: restart 0 alone: validation %.17g; restart 1 alone: %.17g; both: %.17g (restart %d)\n",
           (int)seed_r1, ra.validation_loss, rb.validation_loss, both.validation_loss, both.best_restart);
    CHECK(ra.best_restart == 0 && rb.best_restart == 1);
    CHECK(rb.validation_loss < ra.validation_loss);
    CHECK(both.best_restart == 1);
    CHECK(both.validation_loss == rb.validation_loss);
    CHECK(memcmp(both.net.params, rb.net.params, (size_t)np * sizeof(double)) == 0);
    CHECK(both.epochs_run == ra.epochs_run + rb.epochs_run);
    one.first_restart = -1;
    sf_error bad = {0};
    CHECK(sf_mlp_train(&tr, &va, &one, &rc, &bad) == SF_ERR_INPUT);
    printf("first restart -1: %s\n", bad.message);
    sf_mlp_free(&both.net);
    sf_mlp_free(&ra.net);
    sf_mlp_free(&rb.net);
    sf_mlp_free(&rc.net);
  }

  /* Interrupt after 5 epochs (restart 0), then after 9 more (restart 1), resume. */
  char path[] = "/tmp/skyfit_test_mlp_train_XXXXXX";
  int fd = mkstemp(path);
  if (fd >= 0) close(fd);
  o.checkpoint_path = path;
  o.stop_after_epochs = 5;
  run(&tr, &va, &o, &r3);
  CHECK(r3.interrupted == 1 && r3.epochs_run == 5);
  sf_mlp_free(&r3.net);
  o.resume = 1;
  o.stop_after_epochs = 9;
  run(&tr, &va, &o, &r3);
  CHECK(r3.interrupted == 1);
  sf_mlp_free(&r3.net);
  o.stop_after_epochs = 0;
  run(&tr, &va, &o, &r4);
  int same_resume = !r4.interrupted && memcmp(r1.net.params, r4.net.params, (size_t)np * sizeof(double)) == 0;
  printf("straight vs interrupted twice + resumed: epochs %d vs %d, validation loss %.17g vs %.17g, identical: %d\n",
         r1.epochs_run, r4.epochs_run, r1.validation_loss, r4.validation_loss, same_resume);
  CHECK(same_resume);
  CHECK(r1.epochs_run == r4.epochs_run);
  FILE *left = fopen(path, "rb");
  CHECK(left == NULL);   /* a finished run removes its checkpoint */
  if (left) fclose(left);
  /* A checkpoint of another run is refused. */
  o.resume = 0;
  o.stop_after_epochs = 2;
  run(&tr, &va, &o, &r3);
  sf_mlp_free(&r3.net);
  o.resume = 1;
  o.stop_after_epochs = 0;
  o.seed = 8;
  sf_train_result r5 = {0};
  CHECK(sf_mlp_train(&tr, &va, &o, &r5, &err) == SF_ERR_INPUT);
  sf_mlp_free(&r5.net);
  printf("mismatched checkpoint: %s\n", err.message);
  remove(path);

  /* A large batch sums its gradient in larger chunks (sf_train_chunk_size):
   * the smallest power-of-two multiple of SF_TRAIN_CHUNK that leaves at
   * most SF_TRAIN_CHUNKS_MAX chunks, and the sums still the same for 1 and
   * 2 threads. */
  {
    const long batches[] = {1, 255, 256, 257, 1000, 262144, 262145, 300000, 967680, 1L << 30};
    int rule_holds = 1;
    for (size_t k = 0; k < sizeof batches / sizeof batches[0]; ++k) {
      long b = batches[k], c = sf_train_chunk_size(b);
      long chunks = (b + c - 1) / c, fewer = (b + c / 2 - 1) / (c / 2);
      int power = c % SF_TRAIN_CHUNK == 0 && ((c / SF_TRAIN_CHUNK) & (c / SF_TRAIN_CHUNK - 1)) == 0;
      int smallest = c == SF_TRAIN_CHUNK || fewer > SF_TRAIN_CHUNKS_MAX;
      if (!power || chunks > SF_TRAIN_CHUNKS_MAX || !smallest) {
        printf("chunk size of a batch of %ld: %ld (%ld chunks)\n", b, c, chunks);
        rule_holds = 0;
      }
    }
    CHECK(rule_holds);
    CHECK(sf_train_chunk_size(300000) == 2 * SF_TRAIN_CHUNK);

    sf_dataset big;
    make_data(&big, 300000);
    sf_train_options f;
    sf_train_options_default(&f);
    sf_mlp_shape_parse_layers("2,4,3", &f.shape, &err);
    f.epochs = 3;
    f.batch = 0;   /* the full batch: 586 chunks of 512 */
    f.parallel_work = 0.0;
    f.seed = 11;
    sf_train_result b1 = {0}, b2 = {0};
    f.n_threads = 1;
    run(&big, NULL, &f, &b1);
    f.n_threads = 2;
    run(&big, NULL, &f, &b2);
    int same = b1.net.params && b2.net.params &&
               memcmp(b1.net.params, b2.net.params, (size_t)b1.net.n_params * sizeof(double)) == 0;
    printf("full batch of 300000 (chunks of %ld), 1 vs 2 threads: training loss %.17g vs %.17g, "
           "weights identical: %d\n",
           sf_train_chunk_size(300000), b1.train_loss, b2.train_loss, same);
    CHECK(same);
    /* The first epoch's loss, of the initial network summed in chunks of
     * 512, is the data set's loss summed in chunks of 256: every sample
     * counted once. */
    sf_mlp init_big;
    sf_mlp_init(&init_big, &f.shape);
    sf_mlp_init_xavier(&f.shape, f.seed, 0, init_big.params);
    sf_mlp_loss mse_big = {SF_LOSS_MSE, NULL};
    double first_epoch = NAN;
    f.progress = first_epoch_loss;
    f.progress_ctx = &first_epoch;
    f.epochs = 1;
    sf_train_result b3 = {0};
    run(&big, NULL, &f, &b3);
    CHECK_REL(first_epoch, sf_mlp_dataset_loss(&f.shape, init_big.params, &mse_big, &big, 1), 1e-12);
    sf_mlp_free(&init_big);
    sf_mlp_free(&b3.net);
    sf_mlp_free(&b1.net);
    sf_mlp_free(&b2.net);
    sf_dataset_free(&big);
  }

  /* Learning: the loss of the kept network is far below the initial one. */
  sf_train_options q;
  sf_train_options_default(&q);
  q.shape = o.shape;
  q.epochs = 150;
  q.batch = 64;
  q.seed = 3;
  sf_mlp init;
  sf_mlp_init(&init, &q.shape);
  sf_mlp_init_xavier(&q.shape, q.seed, 0, init.params);
  sf_mlp_loss mse = {SF_LOSS_MSE, NULL};
  double loss0 = sf_mlp_dataset_loss(&q.shape, init.params, &mse, &va, 1);
  sf_train_result rq = {0};
  run(&tr, &va, &q, &rq);
  printf("validation mse: initial %.4g, trained %.4g (ratio %.3g)\n", loss0, rq.validation_loss,
         loss0 / rq.validation_loss);
  CHECK(rq.validation_loss < 1e-2 * loss0);
  /* The kept network's validation loss is the best one seen: recomputing it agrees. */
  CHECK_REL(sf_mlp_dataset_loss(&q.shape, rq.net.params, &mse, &va, 2), rq.validation_loss, 1e-12);

  sf_mlp_free(&init);
  sf_mlp_free(&rq.net);
  sf_mlp_free(&r1.net);
  sf_mlp_free(&r2.net);
  sf_mlp_free(&r4.net);
  sf_dataset_free(&all);
  sf_dataset_free(&tr);
  sf_dataset_free(&va);
  return check_summary();
}
