/* Uses the headers skyfit_generate() writes at build time: prints the
 * transmittance of the zenith and of a ray 5 degrees above the horizon for a
 * viewer on the ground, from the model the scene's budget selected, under
 * its stable name (the selection is in the build folder's
 * skyfit/sky_demo/skyfit/report.md), beside Schuler's Chapman approximation
 * from the second header, whose names start baseline_. */
#include <stdio.h>

#include "sky_baselines.h"
#include "skyfit.h"

int main(void) {
  const float mus[2] = {1.0f, 0.0871557f};
  for (int i = 0; i < 2; ++i) {
    skyfit_vec3 t = skyfit_transmittance(0.0f, mus[i]);
    skyfit_vec3 half = skyfit_transmittance_segment(0.0f, mus[i], 10.0f);
    baseline_vec3 chapman = baseline_chapman_transmittance(0.0f, mus[i]);
    printf("mu %.4f  transmittance %.5f %.5f %.5f  first 10 km %.5f %.5f %.5f  chapman %.5f %.5f %.5f\n", mus[i],
           t.x, t.y, t.z, half.x, half.y, half.z, chapman.x, chapman.y, chapman.z);
  }
  return 0;
}
