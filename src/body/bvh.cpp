#include "pb4u/body/bvh.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "pb4u/util/error.h"

namespace pb4u {
namespace {

constexpr double kDegree = M_PI / 180.0;
// Limits no motion capture file comes near (skeletons nest ~10-30 joints deep, takes last
// seconds to minutes) that keep a hostile file from exhausting the stack or the memory.
constexpr int kMaxJointDepth = 1000;
constexpr double kMaxDurationSeconds = 3600.0;

struct Token {
  std::string text;
  int line;
};

class Tokens {
 public:
  Tokens(const std::string& text, std::string name) : name_(std::move(name)) {
    int line = 1;
    std::string cur;
    for (char c : text) {
      if (std::isspace(static_cast<unsigned char>(c))) {
        if (!cur.empty()) tokens_.push_back({cur, line}), cur.clear();
        if (c == '\n') ++line;
      } else {
        cur += c;
      }
    }
    if (!cur.empty()) tokens_.push_back({cur, line});
    last_line_ = line;
  }
  bool done() const { return pos_ >= tokens_.size(); }
  const std::string& peek() const {
    if (done()) fail("unexpected end of file");
    return tokens_[pos_].text;
  }
  std::string next() {
    const std::string& t = peek();
    ++pos_;
    return t;
  }
  void expect(const std::string& word) {
    int line = done() ? last_line_ : tokens_[pos_].line;
    std::string t = next();
    if (t != word) fail_at(line, "expected '" + word + "', found '" + t + "'");
  }
  double number() {
    int line = done() ? last_line_ : tokens_[pos_].line;
    std::string t = next();
    char* end = nullptr;
    double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !std::isfinite(v))
      fail_at(line, "expected a number, found '" + t + "'");
    return v;
  }
  int line() const { return done() ? last_line_ : tokens_[pos_].line; }
  size_t remaining() const { return tokens_.size() - pos_; }
  [[noreturn]] void fail(const std::string& why) const { fail_at(line(), why); }
  [[noreturn]] void fail_at(int line, const std::string& why) const {
    throw Error(name_ + ": line " + std::to_string(line) + ": " + why);
  }

 private:
  std::vector<Token> tokens_;
  size_t pos_ = 0;
  int last_line_ = 1;
  std::string name_;
};

enum class Channel { Xpos, Ypos, Zpos, Xrot, Yrot, Zrot };

struct Parsed {
  Skeleton skeleton;
  std::vector<std::vector<Channel>> channels;  // per joint
  std::vector<Eigen::RowVector3d> offsets;
};

Channel parse_channel(Tokens& tk) {
  const int line = tk.line();
  const std::string c = tk.next();
  if (c == "Xposition") return Channel::Xpos;
  if (c == "Yposition") return Channel::Ypos;
  if (c == "Zposition") return Channel::Zpos;
  if (c == "Xrotation") return Channel::Xrot;
  if (c == "Yrotation") return Channel::Yrot;
  if (c == "Zrotation") return Channel::Zrot;
  tk.fail_at(line, "unknown channel '" + c + "'");
}

void parse_joint(Tokens& tk, Parsed& p, int parent, double scale, int depth = 0) {
  if (depth > kMaxJointDepth)
    tk.fail("joints nested more than " + std::to_string(kMaxJointDepth) + " deep");
  const std::string name = tk.next();
  const int j = static_cast<int>(p.skeleton.names.size());
  p.skeleton.names.push_back(name);
  p.skeleton.parents.push_back(parent);
  tk.expect("{");
  tk.expect("OFFSET");
  Eigen::RowVector3d off;
  for (int k = 0; k < 3; ++k) off[k] = tk.number() * scale;
  p.offsets.push_back(off);
  p.channels.emplace_back();
  tk.expect("CHANNELS");
  const int line = tk.line();
  const double count = tk.number();
  if (count != std::floor(count) || count < 0 || count > 6)
    tk.fail_at(line, "channel count must be 0..6");
  for (int k = 0; k < static_cast<int>(count); ++k) p.channels[j].push_back(parse_channel(tk));
  for (Channel c : p.channels[j])
    if (parent >= 0 && (c == Channel::Xpos || c == Channel::Ypos || c == Channel::Zpos))
      tk.fail_at(line, "joint '" + name + "': position channels are only supported on the root");
  while (true) {
    const std::string t = tk.peek();
    if (t == "}") {
      tk.next();
      return;
    }
    if (t == "JOINT") {
      tk.next();
      parse_joint(tk, p, j, scale, depth + 1);
    } else if (t == "End") {
      tk.next();
      tk.expect("Site");
      tk.expect("{");
      tk.expect("OFFSET");
      for (int k = 0; k < 3; ++k) tk.number();
      tk.expect("}");
    } else {
      tk.fail("unexpected '" + t + "' in joint '" + name + "'");
    }
  }
}

}  // namespace

BvhFile parse_bvh(const std::string& text, const std::string& name, double scale) {
  Tokens tk(text, name);
  if (tk.done()) throw Error(name + ": empty BVH file");
  tk.expect("HIERARCHY");
  tk.expect("ROOT");
  Parsed p;
  parse_joint(tk, p, -1, scale);
  tk.expect("MOTION");
  tk.expect("Frames:");
  int line = tk.line();
  const double frames = tk.number();
  if (frames < 1 || frames != std::floor(frames)) tk.fail_at(line, "frame count must be >= 1");
  tk.expect("Frame");
  tk.expect("Time:");
  line = tk.line();
  const double frame_time = tk.number();
  if (!(frame_time > 0)) tk.fail_at(line, "frame time must be positive");
  if (frames * frame_time > kMaxDurationSeconds)
    tk.fail_at(line, "the motion would last " + std::to_string(frames * frame_time) + " s, more than " +
                         std::to_string(kMaxDurationSeconds) + " s");
  size_t values_per_frame = 0;
  for (const auto& c : p.channels) values_per_frame += c.size();
  if (values_per_frame == 0) throw Error(name + ": no joint has channels: there is no motion");
  if (frames > static_cast<double>(tk.remaining() / values_per_frame))
    tk.fail("the file holds " + std::to_string(tk.remaining() / values_per_frame) + " of the " +
            std::to_string(static_cast<long long>(frames)) + " frames its header declares");

  BvhFile out;
  out.skeleton = std::move(p.skeleton);
  Skeleton& s = out.skeleton;
  const int J = s.num_joints();
  s.offsets.resize(J, 3);
  for (int j = 0; j < J; ++j) s.offsets.row(j) = p.offsets[j];
  validate_skeleton(s, name);
  out.source_fps = 1.0 / frame_time;
  out.source_frames = static_cast<int>(frames);
  out.motion.fps = out.source_fps;
  out.motion.frames.reserve(out.source_frames);
  for (int f = 0; f < out.source_frames; ++f) {
    Pose pose = rest_pose(s);
    for (int j = 0; j < J; ++j) {
      Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
      for (Channel c : p.channels[j]) {
        const double v = tk.number();
        switch (c) {
          case Channel::Xpos: pose.root.x() = v * scale; break;
          case Channel::Ypos: pose.root.y() = v * scale; break;
          case Channel::Zpos: pose.root.z() = v * scale; break;
          case Channel::Xrot: q = q * Eigen::AngleAxisd(v * kDegree, Eigen::Vector3d::UnitX()); break;
          case Channel::Yrot: q = q * Eigen::AngleAxisd(v * kDegree, Eigen::Vector3d::UnitY()); break;
          case Channel::Zrot: q = q * Eigen::AngleAxisd(v * kDegree, Eigen::Vector3d::UnitZ()); break;
        }
      }
      pose.rotations[j] = q.normalized();
    }
    out.motion.frames.push_back(std::move(pose));
  }
  if (!tk.done()) tk.fail("extra values after the last frame (channel count and data disagree)");
  return out;
}

BvhFile read_bvh(const std::string& path, double fps, double scale) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, "cannot open BVH file");
  std::stringstream ss;
  ss << in.rdbuf();
  BvhFile bvh = parse_bvh(ss.str(), path, scale);
  if (fps > 0) bvh.motion = resample_motion(bvh.motion, fps);
  return bvh;
}

}  // namespace pb4u
