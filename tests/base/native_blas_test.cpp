// The decision behind OPENBLAS_CORETYPE (base/native_blas.h): which kernels to force, and when to
// leave OpenBLAS's own choice.
#include "podium/base/native_blas.h"

#include <gtest/gtest.h>

namespace podium::base {
namespace {

TEST(NativeBlas, AGenericFallbackOnAWideCpuIsReplacedByTheWidestKernels) {
  EXPECT_EQ(openblas_core_override("Prescott", 512), "SkylakeX");
  EXPECT_EQ(openblas_core_override("Nehalem", 256), "Haswell");
  EXPECT_EQ(openblas_core_override("Sandybridge", 512), "SkylakeX");
  EXPECT_EQ(openblas_core_override("Haswell", 512), "SkylakeX");  // AVX2 kernels on an AVX-512 CPU
}

TEST(NativeBlas, AChoiceAsWideAsTheCpuOrUnknownStands) {
  EXPECT_EQ(openblas_core_override("SkylakeX", 512), "");
  EXPECT_EQ(openblas_core_override("Cooperlake", 512), "");
  EXPECT_EQ(openblas_core_override("Zen", 256), "");
  EXPECT_EQ(openblas_core_override("Haswell", 256), "");
  EXPECT_EQ(openblas_core_override("Prescott", 0), "");          // a CPU without AVX2: nothing wider to use
  EXPECT_EQ(openblas_core_override("SomeFutureCore", 512), "");  // a name this table does not know
  EXPECT_EQ(openblas_core_override("", 512), "");
}

TEST(NativeBlas, TheCpuReportsAWidthOpenBlasHasKernelsFor) {
  const int bits = cpu_vector_bits();
  EXPECT_TRUE(bits == 0 || bits == 256 || bits == 512) << bits;
  std::printf("this CPU: %d-bit vectors for OpenBLAS\n", bits);
}

}  // namespace
}  // namespace podium::base
