#include "foxglove_json.h"

#include <charconv>
#include <cmath>
#include <cstring>

namespace ovpc::scenarios::foxglove {
namespace {

// Pieces of the JSON Schemas, named as Foxglove names them.
const std::string kTime = R"({"type":"object","title":"time","properties":{"sec":{"type":"integer","minimum":0},)"
                          R"("nsec":{"type":"integer","minimum":0,"maximum":999999999}}})";
const std::string kVector3 = R"({"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},)"
                             R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]})";
const std::string kPoint3 = R"({"title":"foxglove.Point3","type":"object","properties":{"x":{"type":"number"},)"
                            R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]})";
const std::string kQuaternion = R"({"title":"foxglove.Quaternion","type":"object","properties":{"x":{"type":"number"},)"
                                R"("y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}},"required":["x","y","z","w"]})";
const std::string kPose = R"({"title":"foxglove.Pose","type":"object","properties":{"position":)" + kVector3 +
                          R"(,"orientation":)" + kQuaternion + R"(},"required":["position","orientation"]})";
const std::string kColor = R"({"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
                           R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]})";

std::string Object(const std::string& title, const std::string& properties, const std::string& required) {
  return R"({"title":")" + title + R"(","type":"object","properties":{)" + properties + R"(},"required":[)" + required + "]}";
}
std::string ArrayOf(const std::string& items) { return R"({"type":"array","items":)" + items + "}"; }

std::string PrimitiveSchemas(const std::string& name) {
  const std::string pose = R"("pose":)" + kPose + R"(,"color":)" + kColor;
  if (name == "arrows") {
    return Object("foxglove.ArrowPrimitive",
                  pose + R"(,"shaft_length":{"type":"number"},"shaft_diameter":{"type":"number"},"head_length":{"type":"number"},)"
                         R"("head_diameter":{"type":"number"})",
                  R"("pose","shaft_length","shaft_diameter","head_length","head_diameter","color")");
  }
  if (name == "cubes") return Object("foxglove.CubePrimitive", pose + R"(,"size":)" + kVector3, R"("pose","size","color")");
  if (name == "spheres") return Object("foxglove.SpherePrimitive", pose + R"(,"size":)" + kVector3, R"("pose","size","color")");
  if (name == "cylinders") {
    return Object("foxglove.CylinderPrimitive",
                  pose + R"(,"size":)" + kVector3 + R"(,"bottom_scale":{"type":"number"},"top_scale":{"type":"number"})",
                  R"("pose","size","bottom_scale","top_scale","color")");
  }
  const std::string lists = R"(,"points":)" + ArrayOf(kPoint3) + R"(,"colors":)" + ArrayOf(kColor) +
                            R"(,"indices":{"type":"array","items":{"type":"integer","minimum":0}})";
  if (name == "lines") {
    return Object("foxglove.LinePrimitive",
                  pose + lists + R"(,"type":{"title":"foxglove.LineType","enum":[0,1,2]},"thickness":{"type":"number"},)"
                                 R"("scale_invariant":{"type":"boolean"})",
                  R"("type","pose","thickness","scale_invariant","points","color","colors","indices")");
  }
  return Object("foxglove.TriangleListPrimitive", pose + lists, R"("pose","points","color","colors","indices")");
}

std::string SceneUpdateSchema() {
  std::string entity = R"("timestamp":)" + kTime + R"(,"frame_id":{"type":"string"},"id":{"type":"string"},)"
                       R"("lifetime":{"type":"object","title":"duration","properties":{"sec":{"type":"integer"},"nsec":{"type":"integer"}}},)"
                       R"("frame_locked":{"type":"boolean"},"metadata":)" +
                       ArrayOf(Object("foxglove.KeyValuePair", R"("key":{"type":"string"},"value":{"type":"string"})", R"("key","value")"));
  for (const char* p : {"arrows", "cubes", "spheres", "cylinders", "lines", "triangles"}) {
    entity += std::string(",\"") + p + "\":" + ArrayOf(PrimitiveSchemas(p));
  }
  entity += R"(,"texts":{"type":"array","items":{"type":"object"}},"models":{"type":"array","items":{"type":"object"}})";
  const std::string deletion = Object("foxglove.SceneEntityDeletion",
                                      R"("timestamp":)" + kTime + R"(,"type":{"enum":[0,1]},"id":{"type":"string"})", R"("timestamp","type","id")");
  const std::string entity_schema =
      Object("foxglove.SceneEntity", entity,
             R"("timestamp","frame_id","id","lifetime","frame_locked","metadata","arrows","cubes","spheres","cylinders","lines","triangles","texts","models")");
  return Object("foxglove.SceneUpdate", R"("deletions":)" + ArrayOf(deletion) + R"(,"entities":)" + ArrayOf(entity_schema),
                R"("deletions","entities")");
}

}  // namespace

std::uint64_t Nanoseconds(double time_s) {
  return time_s > 0 ? static_cast<std::uint64_t>(std::llround(time_s * 1e9)) : 0;
}

std::string JsonSchema(std::string_view name) {
  const std::string ts = R"("timestamp":)" + kTime;
  if (name == "foxglove.FrameTransform") {
    return Object("foxglove.FrameTransform",
                  ts + R"(,"parent_frame_id":{"type":"string"},"child_frame_id":{"type":"string"},"translation":)" + kVector3 +
                      R"(,"rotation":)" + kQuaternion,
                  R"("timestamp","parent_frame_id","child_frame_id","translation","rotation")");
  }
  if (name == "foxglove.PoseInFrame") {
    return Object("foxglove.PoseInFrame", ts + R"(,"frame_id":{"type":"string"},"pose":)" + kPose, R"("timestamp","frame_id","pose")");
  }
  if (name == "foxglove.PointCloud") {
    const std::string field = Object("foxglove.PackedElementField",
                                     R"("name":{"type":"string"},"offset":{"type":"integer","minimum":0},)"
                                     R"("type":{"title":"foxglove.NumericType","enum":[0,1,2,3,4,5,6,7,8]})",
                                     R"("name","offset","type")");
    return Object("foxglove.PointCloud",
                  ts + R"(,"frame_id":{"type":"string"},"pose":)" + kPose +
                      R"(,"point_stride":{"type":"integer","minimum":0},"fields":)" + ArrayOf(field) +
                      R"(,"data":{"type":"string","contentEncoding":"base64"})",
                  R"("timestamp","frame_id","pose","point_stride","fields","data")");
  }
  if (name == "foxglove.Log") {
    return Object("foxglove.Log",
                  ts + R"(,"level":{"title":"foxglove.LogLevel","enum":[0,1,2,3,4,5]},"message":{"type":"string"},)"
                       R"("name":{"type":"string"},"file":{"type":"string"},"line":{"type":"integer","minimum":0})",
                  R"("timestamp","level","message","name","file","line")");
  }
  if (name == "foxglove.SceneUpdate") return SceneUpdateSchema();
  if (name == "ovpc.Command") {
    return Object("ovpc.Command", ts + R"(,"steering_rad":{"type":"number"},"speed_mps":{"type":"number"})",
                  R"("timestamp","steering_rad","speed_mps")");
  }
  return "";
}

Json& Json::Str(std::string_view text) {
  s_ += '"';
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      s_ += '\\';
      s_ += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      static const char* kHex = "0123456789abcdef";
      s_ += "\\u00";
      s_ += kHex[(c >> 4) & 0xF];
      s_ += kHex[c & 0xF];
    } else {
      s_ += c;
    }
  }
  s_ += '"';
  return *this;
}

Json& Json::Num(double v, int decimals) {
  if (!std::isfinite(v)) v = 0.0;
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  char* end = r.ptr;
  if (std::memchr(buf, '.', static_cast<std::size_t>(end - buf)) != nullptr) {
    while (end[-1] == '0') --end;
    if (end[-1] == '.') --end;
  }
  if (end - buf == 2 && buf[0] == '-' && buf[1] == '0') {  // -0 rounds to 0
    s_ += '0';
  } else {
    s_.append(buf, end);
  }
  return *this;
}

Json& Json::Int(std::int64_t v) {
  s_ += std::to_string(v);
  return *this;
}

Json& Json::Time(std::uint64_t ns) {
  s_ += "{\"sec\":" + std::to_string(ns / 1000000000u) + ",\"nsec\":" + std::to_string(ns % 1000000000u) + "}";
  return *this;
}

Json& Json::Vec3(const Eigen::Vector3d& v, int decimals) {
  Raw("{\"x\":").Num(v.x(), decimals).Raw(",\"y\":").Num(v.y(), decimals).Raw(",\"z\":").Num(v.z(), decimals);
  return Raw("}");
}

Json& Json::Quat(const Eigen::Quaterniond& q) {
  Raw("{\"x\":").Num(q.x(), 6).Raw(",\"y\":").Num(q.y(), 6).Raw(",\"z\":").Num(q.z(), 6).Raw(",\"w\":").Num(q.w(), 6);
  return Raw("}");
}

Json& Json::Pose(const Eigen::Isometry3d& T) {
  Raw("{\"position\":").Vec3(T.translation()).Raw(",\"orientation\":").Quat(Eigen::Quaterniond(T.linear()).normalized());
  return Raw("}");
}

Json& Json::Color(float r, float g, float b, float a) {
  return Raw("{\"r\":").Num(r, 3).Raw(",\"g\":").Num(g, 3).Raw(",\"b\":").Num(b, 3).Raw(",\"a\":").Num(a, 3).Raw("}");
}

std::string Base64(std::string_view bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  const auto byte = [&bytes](std::size_t k) { return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[k])); };
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 0x3F];
  }
  if (i + 1 == bytes.size()) {
    const std::uint32_t v = byte(i) << 16;
    out += kAlphabet[(v >> 18) & 0x3F];
    out += kAlphabet[(v >> 12) & 0x3F];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const std::uint32_t v = byte(i) << 16 | byte(i + 1) << 8;
    out += kAlphabet[(v >> 18) & 0x3F];
    out += kAlphabet[(v >> 12) & 0x3F];
    out += kAlphabet[(v >> 6) & 0x3F];
    out += '=';
  }
  return out;
}

std::string FrameTransform(std::uint64_t ns, const std::string& parent, const std::string& child, const Eigen::Isometry3d& T) {
  Json j;
  j.Raw("{\"timestamp\":").Time(ns).Raw(",\"parent_frame_id\":").Str(parent).Raw(",\"child_frame_id\":").Str(child);
  j.Raw(",\"translation\":").Vec3(T.translation()).Raw(",\"rotation\":").Quat(Eigen::Quaterniond(T.linear()).normalized());
  return j.Raw("}").str();
}

std::string PoseInFrame(std::uint64_t ns, const std::string& frame, const Eigen::Isometry3d& T) {
  Json j;
  j.Raw("{\"timestamp\":").Time(ns).Raw(",\"frame_id\":").Str(frame).Raw(",\"pose\":").Pose(T);
  return j.Raw("}").str();
}

std::string Log(std::uint64_t ns, int level, const std::string& name, const std::string& message) {
  Json j;
  j.Raw("{\"timestamp\":").Time(ns).Raw(",\"level\":").Int(level).Raw(",\"message\":").Str(message);
  j.Raw(",\"name\":").Str(name).Raw(",\"file\":\"\",\"line\":0}");
  return j.str();
}

std::string PointCloud(std::uint64_t ns, const std::string& frame, const Eigen::Isometry3d& T_frame_cloud,
                       const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint8_t>* flags,
                       const std::string& flag_name) {
  const std::size_t stride = flags ? 13 : 12;
  std::string data(points.size() * stride, '\0');
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float xyz[3] = {static_cast<float>(points[i].x()), static_cast<float>(points[i].y()), static_cast<float>(points[i].z())};
    std::memcpy(&data[i * stride], xyz, sizeof xyz);  // little-endian, as x86 and ARM Linux store it
    if (flags) data[i * stride + 12] = static_cast<char>(i < flags->size() ? (*flags)[i] : 0);
  }
  Json j;
  j.Raw("{\"timestamp\":").Time(ns).Raw(",\"frame_id\":").Str(frame).Raw(",\"pose\":").Pose(T_frame_cloud);
  j.Raw(",\"point_stride\":").Int(static_cast<std::int64_t>(stride));
  j.Raw(R"(,"fields":[{"name":"x","offset":0,"type":7},{"name":"y","offset":4,"type":7},{"name":"z","offset":8,"type":7})");
  if (flags) j.Raw(",{\"name\":").Str(flag_name).Raw(",\"offset\":12,\"type\":1}");
  j.Raw("],\"data\":\"").Raw(Base64(data)).Raw("\"}");
  return j.str();
}

std::string SceneUpdate(std::uint64_t ns, const std::vector<Entity>& entities) {
  Json j;
  j.Raw("{\"deletions\":[],\"entities\":[");
  for (std::size_t e = 0; e < entities.size(); ++e) {
    const Entity& en = entities[e];
    if (e > 0) j.Raw(",");
    j.Raw("{\"timestamp\":").Time(ns).Raw(",\"frame_id\":").Str(en.frame_id).Raw(",\"id\":").Str(en.id);
    j.Raw(",\"lifetime\":{\"sec\":0,\"nsec\":0},\"frame_locked\":false,\"metadata\":[");
    for (std::size_t m = 0; m < en.metadata.size(); ++m) {
      j.Raw(m > 0 ? ",{\"key\":" : "{\"key\":").Str(en.metadata[m].first).Raw(",\"value\":").Str(en.metadata[m].second).Raw("}");
    }
    j.Raw("],\"arrows\":[").Raw(en.arrows).Raw("],\"cubes\":[").Raw(en.cubes).Raw("],\"spheres\":[").Raw(en.spheres);
    j.Raw("],\"cylinders\":[").Raw(en.cylinders).Raw("],\"lines\":[").Raw(en.lines).Raw("],\"triangles\":[").Raw(en.triangles);
    j.Raw("],\"texts\":[],\"models\":[]}");
  }
  return j.Raw("]}").str();
}

}  // namespace ovpc::scenarios::foxglove
