// Frame-to-frame RGB-D odometry with OpenCV's rgbd module (see odometry.hpp).
#include "mereo/cognitive/odometry.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>

#include "mereo/core/error.hpp"

namespace mereo::cognitive {

namespace {

/// OpenCV's 4x4 CV_64F motion and ours.
Pose to_pose(const cv::Mat& Rt) {
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = Rt.at<double>(r, c);
  return Pose(M);
}
cv::Mat to_mat(const Pose& P) {
  cv::Mat Rt(4, 4, CV_64F);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) Rt.at<double>(r, c) = P.matrix()(r, c);
  return Rt;
}

/// How many of the source's points (every 4th pixel) land, moved by Rt, within 1 cm of the
/// destination's depth at their projection.
int alignment(const cv::Mat& src, const cv::Mat& dst, const Intrinsics& K, const Pose& Rt) {
  int n = 0;
  for (int v = 0; v < src.rows; v += 4)
    for (int u = 0; u < src.cols; u += 4) {
      const float z = src.at<float>(v, u);
      if (!(z > 0)) continue;
      const Eigen::Vector3d q = Rt * K.point(u, v, z);
      if (!(q.z() > 0)) continue;
      const Eigen::Vector2i px = K.pixel(q);
      const int uu = px.x(), vv = px.y();
      if (uu < 0 || vv < 0 || uu >= dst.cols || vv >= dst.rows) continue;
      const float d = dst.at<float>(vv, uu);
      n += d > 0 && std::abs(d - q.z()) < 0.01;
    }
  return n;
}

}  // namespace

struct Odometry::State {
  cv::Ptr<cv::rgbd::RgbdICPOdometry> odometry;
  Intrinsics intrinsics;
  cv::Ptr<cv::rgbd::OdometryFrame> frame;  // the previous frame, its pyramids and normals cached
  Pose pose = Pose::Identity();
  std::optional<Pose> last_motion;  // the previous frame-to-frame motion: the next one's first guess
  bool started = false;
};

Odometry::Odometry(OdometryOptions options) : state_(std::make_unique<State>()), options_(options) {}
Odometry::~Odometry() = default;
Odometry::Odometry(Odometry&&) noexcept = default;
Odometry& Odometry::operator=(Odometry&&) noexcept = default;

Pose Odometry::update(const Frame& frame, const std::vector<Segment>& segments, const std::optional<TablePlane>& table) {
  State& s = *state_;
  if (frame.depth.empty()) throw InputError("odometry: frame " + frame.id + " has no depth");
  const int H = frame.rows(), W = frame.cols();
  cv::Mat depth(H, W, CV_32F);
  cv::Mat mask(H, W, CV_8U);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const float z = frame.depth(v, u);
      const bool ok = std::isfinite(z) && z >= options_.min_depth && z <= options_.max_depth;
      depth.at<float>(v, u) = ok ? z : 0.f;
      mask.at<std::uint8_t>(v, u) = ok ? 255 : 0;
    }
  cv::Mat gray;
  if (!frame.color.empty()) {
    cv::Mat rgb(H, W, CV_8UC3, const_cast<std::uint8_t*>(frame.color.data()));
    cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
  } else {
    gray = cv::Mat(H, W, CV_8U, cv::Scalar(128));
  }
  if (!s.odometry || !(s.intrinsics == frame.intrinsics)) {
    const auto& K = frame.intrinsics;
    const cv::Mat camera = (cv::Mat_<float>(3, 3) << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
    // five pyramid levels (the default four miss a turn of several degrees at the first step)
    s.odometry = cv::rgbd::RgbdICPOdometry::create(camera, float(options_.min_depth), float(options_.max_depth),
                                                   float(options_.max_depth_difference),
                                                   cv::rgbd::Odometry::DEFAULT_MAX_POINTS_PART(), {10, 10, 10, 10, 10},
                                                   {10, 10, 10, 10, 10});
    // a hand-held or orbiting camera moves up to ~20 cm and 15 degrees between frames
    s.odometry->setMaxTranslation(0.4);
    s.odometry->setMaxRotation(30);
    s.intrinsics = frame.intrinsics;
  }
  // the frame's pyramids and normals, computed once for both alignments below and kept for the
  // next frame's
  cv::Ptr<cv::rgbd::OdometryFrame> current = cv::rgbd::OdometryFrame::create(gray, depth, mask);
  s.odometry->prepareFrameCache(current, cv::rgbd::OdometryFrame::CACHE_ALL);
  const Pose previous = s.pose;
  if (s.started) {
    // a camera moves smoothly: the last motion is the first guess of this one; no motion is the
    // fallback, taken when the guess fails or aligns clearly fewer points (a planar table slides
    // along itself, so a few more aligned points do not make a motion right)
    cv::Mat guessed, plain;
    Pose Rt = Pose::Identity();
    int with_guess = -1, without = -1;
    if (s.last_motion && s.odometry->compute(s.frame, current, guessed, to_mat(*s.last_motion)))
      Rt = to_pose(guessed), with_guess = alignment(s.frame->depth, depth, frame.intrinsics, Rt);
    if (s.odometry->compute(s.frame, current, plain)) {
      const Pose P = to_pose(plain);
      without = alignment(s.frame->depth, depth, frame.intrinsics, P);
      if (with_guess < 0 || with_guess < 0.8 * without) Rt = P, with_guess = without;
    }
    if (with_guess >= 0 && s.last_motion) {
      // a camera moves smoothly: a motion far from the last one is the alignment failing (an
      // untextured view sliding along the table); the last motion stands in for it
      const Pose change = s.last_motion->inverse() * Rt;
      if (change.translation().norm() > options_.max_jump ||
          Eigen::AngleAxisd(change.linear()).angle() > options_.max_turn_deg * M_PI / 180.0) {
        Rt = *s.last_motion;
        ++jumps_;
      }
    }
    if (with_guess >= 0) {
      // dst_p = Rt * src_p: this camera's points in the previous camera's frame are Rt^-1 p
      s.pose = s.pose * Rt.inverse();
    } else {
      ++lost_;
    }
  }
  fix_ = LandmarkFix{};
  fix_.camera_to_world = s.pose;
  if (table) {
    fix_ = locate(map_, *table, segments, s.pose, options_.landmarks);
    s.pose = fix_.camera_to_world;
    if (!map_.table || (fix_.plane && (map_.landmarks.empty() || fix_.matched >= 1)))
      add_to_map(map_, *table, segments, s.pose, options_.landmarks);
  }
  // the motion taken (corrected or not) is the next frame's first guess
  if (s.started) s.last_motion = Pose(s.pose.inverse() * previous);
  s.started = true;
  s.frame = current;
  return s.pose;
}

}  // namespace mereo::cognitive
