/* Uses the headers skyfit_generate() writes at build time: prints the
 * transmittance of the zenith and of a ray 5 degrees above the horizon for a
 * viewer on the ground, from each analytic baseline. */
#include <stdio.h>

#include "skyfit.h"

int main(void) {
  const float mus[2] = {1.0f, 0.0871557f};
  for (int i = 0; i < 2; ++i) {
    skyfit_vec3 naive = skyfit_naive_transmittance(0.0f, mus[i]);
    skyfit_vec3 chapman = skyfit_chapman_transmittance(0.0f, mus[i]);
    skyfit_vec3 taylor = skyfit_taylor_transmittance(0.0f, mus[i]);
    printf("mu %.4f  naive %.5f %.5f %.5f  chapman %.5f %.5f %.5f  taylor %.5f %.5f %.5f\n",
           mus[i], naive.x, naive.y, naive.z, chapman.x, chapman.y, chapman.z, taylor.x,
           taylor.y, taylor.z);
  }
  return 0;
}
