// lambertian.cl: Lambertian shading of SH light without visibility (the SfSNet image model).
//
// Written once for both targets: OpenCL C 1.2 (the __kernel wrappers at the end) and C++ (the
// plugin's lambertian_cpu.cpp #includes this file for the CPU twins of the same formulas).
// Layouts (P = H * W pixels, item = n * P + p): albedo, normal, image, shading [N,3,P];
// light [N,27] channel-major (R0..R8 G0..G8 B0..B8); mask [N,1,P] (rendered where > 0.5).
// Per pixel: n^ = normal / |normal|, c_i = A_l Y_i(n^) (A = pi, 2pi/3, pi/4),
// shading_ch = (1/pi) sum_i L_ch,i c_i, image = albedo * shading. Masked-out pixels and normals
// shorter than 1e-8 give 0 and no gradient.

#ifdef __OPENCL_VERSION__
#define LB_GLOBAL __global
#define LB_SQRT(x) sqrt(x)
#else
#define LB_GLOBAL
#define LB_SQRT(x) std::sqrt(x)
#endif

#define LB_INV_PI 0.318309886183790672f

// The nine clamped-cosine-weighted SH basis values at the unit direction (x, y, z).
void lb_cosine(float x, float y, float z, float* c) {
  const float a0 = 3.14159265358979f, a1 = 2.09439510239320f, a2 = 0.785398163397448f;
  c[0] = a0 * 0.282094791773878f;
  c[1] = a1 * 0.488602511902920f * y;
  c[2] = a1 * 0.488602511902920f * z;
  c[3] = a1 * 0.488602511902920f * x;
  c[4] = a2 * 1.09254843059208f * x * y;
  c[5] = a2 * 1.09254843059208f * y * z;
  c[6] = a2 * 0.315391565252520f * (3.0f * z * z - 1.0f);
  c[7] = a2 * 1.09254843059208f * x * z;
  c[8] = a2 * 0.546274215296040f * (x * x - y * y);
}

// d c_i / d(x, y, z) as g[3 i + axis].
void lb_cosine_gradient(float x, float y, float z, float* g) {
  const float a1 = 2.09439510239320f * 0.488602511902920f;
  const float a2 = 0.785398163397448f * 1.09254843059208f;
  const float a20 = 0.785398163397448f * 0.315391565252520f;
  const float a22 = 0.785398163397448f * 0.546274215296040f;
  for (int k = 0; k < 27; ++k) g[k] = 0.0f;
  g[4] = a1;
  g[8] = a1;
  g[9] = a1;
  g[12] = a2 * y; g[13] = a2 * x;
  g[16] = a2 * z; g[17] = a2 * y;
  g[20] = 6.0f * a20 * z;
  g[21] = a2 * z; g[23] = a2 * x;
  g[24] = 2.0f * a22 * x; g[25] = -2.0f * a22 * y;
}

// Unit normal of pixel p of image n into u; returns its length (0: not rendered).
float lb_unit_normal(LB_GLOBAL const float* normal, LB_GLOBAL const float* mask, int has_mask,
                     int n, int p, int pixels, float* u) {
  if (has_mask && mask[n * pixels + p] <= 0.5f) return 0.0f;
  const float x = normal[(n * 3 + 0) * pixels + p], y = normal[(n * 3 + 1) * pixels + p],
              z = normal[(n * 3 + 2) * pixels + p];
  const float length = LB_SQRT(x * x + y * y + z * z);
  if (!(length > 1e-8f)) return 0.0f;
  u[0] = x / length;
  u[1] = y / length;
  u[2] = z / length;
  return length;
}

void lb_forward_item(int item, LB_GLOBAL const float* albedo, LB_GLOBAL const float* normal,
                     LB_GLOBAL const float* light, LB_GLOBAL const float* mask,
                     LB_GLOBAL float* image, LB_GLOBAL float* shading, int has_mask, int pixels) {
  const int n = item / pixels, p = item % pixels;
  float u[3] = {0.0f, 0.0f, 0.0f}, c[9];
  const float length = lb_unit_normal(normal, mask, has_mask, n, p, pixels, u);
  lb_cosine(u[0], u[1], u[2], c);
  for (int ch = 0; ch < 3; ++ch) {
    float s = 0.0f;
    if (length > 0.0f)
      for (int i = 0; i < 9; ++i) s += light[n * 27 + ch * 9 + i] * c[i];
    s *= LB_INV_PI;
    const int at = (n * 3 + ch) * pixels + p;
    shading[at] = s;
    image[at] = albedo[at] * s;
  }
}

// Per pixel: the albedo and normal gradients. flags: 1 d_image, 2 d_shading given; 4 albedo,
// 8 normal wanted; 16 accumulate albedo, 32 accumulate normal.
void lb_backward_item(int item, LB_GLOBAL const float* albedo, LB_GLOBAL const float* normal,
                      LB_GLOBAL const float* light, LB_GLOBAL const float* mask,
                      LB_GLOBAL const float* d_image, LB_GLOBAL const float* d_shading,
                      LB_GLOBAL float* d_albedo, LB_GLOBAL float* d_normal, int has_mask,
                      int pixels, int flags) {
  const int n = item / pixels, p = item % pixels;
  float u[3] = {0.0f, 0.0f, 0.0f}, c[9], g[27];
  const float length = lb_unit_normal(normal, mask, has_mask, n, p, pixels, u);
  float du[3] = {0.0f, 0.0f, 0.0f};
  lb_cosine(u[0], u[1], u[2], c);  // unused (length 0) where the pixel is not rendered
  lb_cosine_gradient(u[0], u[1], u[2], g);
  for (int ch = 0; ch < 3; ++ch) {
    const int at = (n * 3 + ch) * pixels + p;
    float s = 0.0f;
    if (length > 0.0f)
      for (int i = 0; i < 9; ++i) s += light[n * 27 + ch * 9 + i] * c[i];
    s *= LB_INV_PI;
    const float di = (flags & 1) ? d_image[at] : 0.0f;
    const float grad_s = di * albedo[at] + ((flags & 2) ? d_shading[at] : 0.0f);
    if (flags & 4) d_albedo[at] = ((flags & 16) ? d_albedo[at] : 0.0f) + di * s;
    if (length > 0.0f)
      for (int i = 0; i < 9; ++i)
        for (int axis = 0; axis < 3; ++axis)
          du[axis] += grad_s * LB_INV_PI * light[n * 27 + ch * 9 + i] * g[3 * i + axis];
  }
  if (flags & 8) {
    // Through the normalisation: d normal = (du - u (u . du)) / |normal|.
    const float dot = u[0] * du[0] + u[1] * du[1] + u[2] * du[2];
    for (int axis = 0; axis < 3; ++axis) {
      const int at = (n * 3 + axis) * pixels + p;
      const float value = length > 0.0f ? (du[axis] - u[axis] * dot) / length : 0.0f;
      d_normal[at] = ((flags & 32) ? d_normal[at] : 0.0f) + value;
    }
  }
}

// Per light coefficient (item = n * 27 + ch * 9 + i): the sum over the image's pixels.
// flags as above plus 64: accumulate into d_light.
void lb_light_item(int item, LB_GLOBAL const float* albedo, LB_GLOBAL const float* normal,
                   LB_GLOBAL const float* mask, LB_GLOBAL const float* d_image,
                   LB_GLOBAL const float* d_shading, LB_GLOBAL float* d_light, int has_mask,
                   int pixels, int flags) {
  const int n = item / 27, ch = (item % 27) / 9, i = item % 9;
  float sum = 0.0f, u[3], c[9];
  for (int p = 0; p < pixels; ++p) {
    if (lb_unit_normal(normal, mask, has_mask, n, p, pixels, u) <= 0.0f) continue;
    lb_cosine(u[0], u[1], u[2], c);
    const int at = (n * 3 + ch) * pixels + p;
    const float grad_s = ((flags & 1) ? d_image[at] * albedo[at] : 0.0f) +
                         ((flags & 2) ? d_shading[at] : 0.0f);
    sum += grad_s * LB_INV_PI * c[i];
  }
  d_light[item] = ((flags & 64) ? d_light[item] : 0.0f) + sum;
}

#ifdef __OPENCL_VERSION__
__kernel void lambertian_forward(__global const float* albedo, __global const float* normal,
                                 __global const float* light, __global const float* mask,
                                 __global float* image, __global float* shading, int has_mask,
                                 int pixels) {
  lb_forward_item((int)get_global_id(0), albedo, normal, light, mask, image, shading, has_mask,
                  pixels);
}

__kernel void lambertian_backward(__global const float* albedo, __global const float* normal,
                                  __global const float* light, __global const float* mask,
                                  __global const float* d_image, __global const float* d_shading,
                                  __global float* d_albedo, __global float* d_normal,
                                  int has_mask, int pixels, int flags) {
  lb_backward_item((int)get_global_id(0), albedo, normal, light, mask, d_image, d_shading,
                   d_albedo, d_normal, has_mask, pixels, flags);
}

__kernel void lambertian_light(__global const float* albedo, __global const float* normal,
                               __global const float* mask, __global const float* d_image,
                               __global const float* d_shading, __global float* d_light,
                               int has_mask, int pixels, int flags) {
  lb_light_item((int)get_global_id(0), albedo, normal, mask, d_image, d_shading, d_light,
                has_mask, pixels, flags);
}
#endif
