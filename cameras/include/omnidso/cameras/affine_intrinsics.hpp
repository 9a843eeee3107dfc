#pragma once
// The affine step every camera model ends with: u = fx·m_x + cx, v = fy·m_y + cy, m the
// model's own (normalised or distorted) coordinates. Unprojecting, m = ((u − cx)/fx,
// (v − cy)/fy), so a model's ∂bearing/∂m becomes
//   ∂bearing/∂(u, v)            = [∂b/∂m_x / fx,  ∂b/∂m_y / fy]
//   ∂bearing/∂(fx, fy, cx, cy)  = [−∂b/∂m_x m_x/fx,  −∂b/∂m_y m_y/fy,  −∂b/∂m_x/fx,  −∂b/∂m_y/fy]
// (∂m/∂f = −m/f, ∂m/∂c = −1/f). The one place for this chain rule; the model's own
// parameters (columns 4…) are each model's business.

namespace omnidso {

// Either output may be null; d_bearing_d_params gets its first four columns.
template <typename Mat32, typename Vec2, typename Scalar, typename UvJacobian, typename ParamsJacobian>
void chainAffineIntrinsics(const Mat32& d_bearing_d_m, const Vec2& m, const Scalar& fx,
                           const Scalar& fy, UvJacobian* d_bearing_d_uv,
                           ParamsJacobian* d_bearing_d_params) {
  if (d_bearing_d_uv) {
    d_bearing_d_uv->col(0) = d_bearing_d_m.col(0) / fx;
    d_bearing_d_uv->col(1) = d_bearing_d_m.col(1) / fy;
  }
  if (d_bearing_d_params) {
    d_bearing_d_params->col(0) = -d_bearing_d_m.col(0) * m.x() / fx;
    d_bearing_d_params->col(1) = -d_bearing_d_m.col(1) * m.y() / fy;
    d_bearing_d_params->col(2) = -d_bearing_d_m.col(0) / fx;
    d_bearing_d_params->col(3) = -d_bearing_d_m.col(1) / fy;
  }
}

}  // namespace omnidso
