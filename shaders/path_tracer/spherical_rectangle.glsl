// Uniform sampling of the solid angle a rectangle subtends at a point: Urena, Fajardo and King 2013,
// "An Area-Preserving Parametrization for Spherical Rectangles" (EGSR). The density is 1 / S in solid
// angle everywhere on the rectangle, so a light sample's weight no longer carries the 1 / d^2 and
// cos(light) factors that make area sampling noisy close to the light or to its plane.
#ifndef PATH_TRACER_SPHERICAL_RECTANGLE_GLSL
#define PATH_TRACER_SPHERICAL_RECTANGLE_GLSL

// The angle of the vector (x, y), y >= 0, in [0, pi], accurate to float rounding. The built-in acos
// and atan may be far less accurate (Vulkan allows 4096 ulp; lavapipe's biased S by 0.07 %): two
// half-angle steps, atan(t) = 2 atan(t / (1 + sqrt(1 + t^2))), bring t = y / x below tan(pi / 16),
// where the Taylor series to t^15 is exact in float.
float precise_angle(float y, float x) {
  if (y == 0.0 && x == 0.0) return 0.0;
  bool steep = y > abs(x);
  float t = steep ? abs(x) / y : y / abs(x);  // in [0, 1]
  t = t / (1.0 + sqrt(1.0 + t * t));
  t = t / (1.0 + sqrt(1.0 + t * t));
  float t2 = t * t;
  float a = 4.0 * t *
            (1.0 + t2 * (-1.0 / 3.0 + t2 * (1.0 / 5.0 + t2 * (-1.0 / 7.0 + t2 * (1.0 / 9.0 +
            t2 * (-1.0 / 11.0 + t2 * (1.0 / 13.0 - t2 / 15.0)))))));
  if (steep) a = 0.5 * PI - a;
  return x < 0.0 ? PI - a : a;
}

// The solid angle of the triangle a, b, c (seen from the origin) whose determinant a . (b x c) is det
// > 0, by Van Oosterom and Strackee (1983): tan(omega / 2) = det / (|a||b||c| + (a.b)|c| + (a.c)|b| +
// (b.c)|a|). Unlike the angle sum it has no cancellation for small triangles.
float triangle_solid_angle(vec3 a, vec3 b, vec3 c, float det) {
  float la = length(a), lb = length(b), lc = length(c);
  return 2.0 * precise_angle(det, la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
}

struct SphericalRectangle {
  vec3 o, x, y, z;         // the point and a frame with x, y along the edges, the rectangle at z = z0 < 0
  float x0, x1, y0, y1, z0;
  float b0, b1, k;         // the two edge-plane normals' z and the angle offset of the parametrization
  float solid_angle;       // S
};

// The rectangle `corner + [0, 1] ex + [0, 1] ey` seen from `o` (which must not lie in its plane).
SphericalRectangle spherical_rectangle(vec3 o, vec3 corner, vec3 ex, vec3 ey) {
  SphericalRectangle r;
  float ex_length = length(ex), ey_length = length(ey);
  r.o = o;
  r.x = ex / ex_length;
  r.y = ey / ey_length;
  r.z = cross(r.x, r.y);
  vec3 d = corner - o;
  r.x0 = dot(d, r.x);
  r.y0 = dot(d, r.y);
  r.z0 = dot(d, r.z);
  if (r.z0 > 0.0) {  // orient the frame so the rectangle lies below the point
    r.z0 = -r.z0;
    r.z = -r.z;
  }
  r.x1 = r.x0 + ex_length;
  r.y1 = r.y0 + ey_length;
  // Outward normals of the four planes through o and an edge; the spherical rectangle's interior angles
  // are pi minus the angles between neighbouring normals (its area is their sum minus 2 pi, which the
  // two triangles give without cancellation).
  vec3 v00 = vec3(r.x0, r.y0, r.z0), v01 = vec3(r.x0, r.y1, r.z0);
  vec3 v10 = vec3(r.x1, r.y0, r.z0), v11 = vec3(r.x1, r.y1, r.z0);
  vec3 n0 = normalize(cross(v00, v10)), n2 = normalize(cross(v11, v01)), n3 = normalize(cross(v01, v00));
  float g2 = precise_angle(length(cross(n2, n3)), -dot(n2, n3));
  float g3 = precise_angle(length(cross(n3, n0)), -dot(n3, n0));
  r.b0 = n0.z;
  r.b1 = n2.z;
  r.k = 2.0 * PI - g2 - g3;
  float det = -r.z0 * ex_length * ey_length;  // of (v00, v10, v11) and of (v00, v11, v01)
  r.solid_angle = triangle_solid_angle(v00, v10, v11, det) + triangle_solid_angle(v00, v11, v01, det);
  return r;
}

// The point of the rectangle at (u, v) in [0, 1)^2, uniformly distributed in solid angle: u picks the
// sub-rectangle [x0, xu] holding the fraction u of S (a closed-form inversion), v the height along it.
vec3 sample_spherical_rectangle(SphericalRectangle r, vec2 u) {
  float au = u.x * r.solid_angle + r.k;
  if (au > PI) au -= 2.0 * PI;  // the same angle in [-pi, pi], where Vulkan bounds sin and cos
  float s = sin(au);
  s = abs(s) < 1e-7 ? (s < 0.0 ? -1e-7 : 1e-7) : s;
  float fu = (cos(au) * r.b0 - r.b1) / s;
  float cu = clamp((fu > 0.0 ? 1.0 : -1.0) * inversesqrt(fu * fu + r.b0 * r.b0), -1.0, 1.0);
  float xu = clamp(-(cu * r.z0) / max(sqrt(1.0 - cu * cu), 1e-20), r.x0, r.x1);
  float d = sqrt(xu * xu + r.z0 * r.z0);
  float h0 = r.y0 / sqrt(d * d + r.y0 * r.y0), h1 = r.y1 / sqrt(d * d + r.y1 * r.y1);
  float hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
  float yv = hv2 < 1.0 - 1e-6 ? clamp(hv * d / sqrt(1.0 - hv2), r.y0, r.y1) : r.y1;
  return r.o + xu * r.x + yv * r.y + r.z0 * r.z;
}

#endif
