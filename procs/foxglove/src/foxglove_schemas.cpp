#include "ucon/foxglove/foxglove_schemas.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <utility>
#include <vector>

namespace ucon {
namespace foxglove {

namespace {

using Json = nlohmann::ordered_json;

Json number(const char* d) { return {{"type", "number"}, {"description", d}}; }
Json integer(const char* d) { return {{"type", "integer"}, {"minimum", 0}, {"description", d}}; }
Json text(const char* d) { return {{"type", "string"}, {"description", d}}; }
Json boolean(const char* d) { return {{"type", "boolean"}, {"description", d}}; }
Json bytes(const char* d) { return {{"type", "string"}, {"contentEncoding", "base64"}, {"description", d}}; }
Json arrayOf(Json items, const char* d) { return {{"type", "array"}, {"items", std::move(items)}, {"description", d}}; }

Json object(const char* title, const char* d, Json properties) {
  Json o = {{"type", "object"}};
  if (title) o["title"] = title;
  o["description"] = d;
  o["properties"] = std::move(properties);
  return o;
}

// Enumeration as Foxglove reads it: oneOf alternatives with a title and a numeric const.
Json enumeration(const char* title, const char* d, const std::vector<std::pair<const char*, int>>& values) {
  Json alternatives = Json::array();
  for (const auto& [name, v] : values) alternatives.push_back({{"title", name}, {"const", v}});
  return {{"title", title}, {"description", d}, {"oneOf", std::move(alternatives)}};
}

Json time(const char* d) {
  return {{"type", "object"},
          {"title", "time"},
          {"description", d},
          {"properties",
           {{"sec", {{"type", "integer"}, {"minimum", 0}}},
            {"nsec", {{"type", "integer"}, {"minimum", 0}, {"maximum", 999999999}}}}}};
}

Json duration(const char* d) {
  return {{"type", "object"},
          {"title", "duration"},
          {"description", d},
          {"properties",
           {{"sec", {{"type", "integer"}}},
            {"nsec", {{"type", "integer"}, {"minimum", 0}, {"maximum", 999999999}}}}}};
}

Json vector3(const char* d) {
  return object("foxglove.Vector3", d, {{"x", number("x [m]")}, {"y", number("y [m]")}, {"z", number("z [m]")}});
}

Json vector2(const char* d) {
  return object("foxglove.Vector2", d, {{"x", number("x [m]")}, {"y", number("y [m]")}});
}

Json point3(const char* d) {
  return object("foxglove.Point3", d, {{"x", number("x [m]")}, {"y", number("y [m]")}, {"z", number("z [m]")}});
}

Json quaternion(const char* d) {
  return object("foxglove.Quaternion", d,
                {{"x", number("x")}, {"y", number("y")}, {"z", number("z")}, {"w", number("w")}});
}

Json pose(const char* d) {
  return object("foxglove.Pose", d,
                {{"position", vector3("position [m]")}, {"orientation", quaternion("orientation")}});
}

Json color(const char* d) {
  return object("foxglove.Color", d,
                {{"r", number("red, 0..1")}, {"g", number("green, 0..1")}, {"b", number("blue, 0..1")},
                 {"a", number("alpha (opacity), 0..1")}});
}

Json packedField() {
  return object("foxglove.PackedElementField", "one field of each packed element",
                {{"name", text("field name")},
                 {"offset", integer("byte offset of the field within an element")},
                 {"type", enumeration("foxglove.NumericType", "type of the field (integers little-endian)",
                                      {{"UNKNOWN", 0}, {"UINT8", 1}, {"INT8", 2}, {"UINT16", 3}, {"INT16", 4},
                                       {"UINT32", 5}, {"INT32", 6}, {"FLOAT32", 7}, {"FLOAT64", 8}})}});
}

Json pointCloud() {
  return object("foxglove.PointCloud", "points with packed fields (x, y, z and more) in a frame",
                {{"timestamp", time("time of the points")},
                 {"frame_id", text("frame of reference")},
                 {"pose", pose("origin of the points in that frame")},
                 {"point_stride", integer("bytes from one point to the next in `data`")},
                 {"fields", arrayOf(packedField(), "fields of each point")},
                 {"data", bytes("the points, `point_stride` bytes each")}});
}

Json frameTransform() {
  return object("foxglove.FrameTransform", "pose of a child frame in its parent frame",
                {{"timestamp", time("time of the transform")},
                 {"parent_frame_id", text("parent frame")},
                 {"child_frame_id", text("child frame")},
                 {"translation", vector3("child origin in the parent frame [m]")},
                 {"rotation", quaternion("child orientation in the parent frame")}});
}

Json poseInFrame() {
  return object("foxglove.PoseInFrame", "a pose in a frame",
                {{"timestamp", time("time of the pose")},
                 {"frame_id", text("frame of reference")},
                 {"pose", pose("the pose")}});
}

Json grid() {
  return object("foxglove.Grid", "a 2-D grid of cells with packed fields",
                {{"timestamp", time("time of the grid")},
                 {"frame_id", text("frame of reference")},
                 {"pose", pose("origin of the grid's corner cell (cell 0, 0) in the frame")},
                 {"column_count", integer("cells per row")},
                 {"cell_size", vector2("cell size along x (columns) and y (rows) [m]")},
                 {"row_stride", integer("bytes from one row to the next in `data`")},
                 {"cell_stride", integer("bytes from one cell to the next in a row")},
                 {"fields", arrayOf(packedField(), "fields of each cell")},
                 {"data", bytes("the cells, row by row from the origin")}});
}

Json sceneUpdate() {
  const Json colour = color("colour");
  Json arrow = object("foxglove.ArrowPrimitive", "an arrow",
                      {{"pose", pose("tail position; the arrow points along the pose's +x")},
                       {"shaft_length", number("shaft length [m]")},
                       {"shaft_diameter", number("shaft diameter [m]")},
                       {"head_length", number("head length [m]")},
                       {"head_diameter", number("head diameter [m]")},
                       {"color", colour}});
  Json cube = object("foxglove.CubePrimitive", "a box",
                     {{"pose", pose("centre and orientation")}, {"size", vector3("size [m]")}, {"color", colour}});
  Json sphere = object("foxglove.SpherePrimitive", "a sphere or ellipsoid",
                       {{"pose", pose("centre and orientation")}, {"size", vector3("diameters [m]")}, {"color", colour}});
  Json cylinder = object("foxglove.CylinderPrimitive", "a cylinder (or cone) along the pose's z axis",
                         {{"pose", pose("centre and orientation")},
                          {"size", vector3("x, y: diameters of the base, z: height [m]")},
                          {"bottom_scale", number("scale of the bottom face, 0..1")},
                          {"top_scale", number("scale of the top face, 0..1")},
                          {"color", colour}});
  Json line = object("foxglove.LinePrimitive", "a polyline",
                     {{"type", enumeration("foxglove.LineType", "how the points connect",
                                           {{"LINE_STRIP", 0}, {"LINE_LOOP", 1}, {"LINE_LIST", 2}})},
                      {"pose", pose("origin of the points")},
                      {"thickness", number("line width [m], or pixels when scale_invariant")},
                      {"scale_invariant", boolean("thickness in pixels")},
                      {"points", arrayOf(point3("vertex"), "vertices")},
                      {"color", colour},
                      {"colors", arrayOf(color("colour"), "per-vertex colours (empty: `color`)")},
                      {"indices", arrayOf({{"type", "integer"}, {"minimum", 0}}, "vertex order (empty: as listed)")}});
  Json triangles = object("foxglove.TriangleListPrimitive", "triangles, three vertices (or indices) each",
                          {{"pose", pose("origin of the points")},
                           {"points", arrayOf(point3("vertex"), "vertices")},
                           {"color", colour},
                           {"colors", arrayOf(color("colour"), "per-vertex colours (empty: `color`)")},
                           {"indices", arrayOf({{"type", "integer"}, {"minimum", 0}},
                                               "three vertex indices per triangle (empty: as listed)")}});
  Json textPrimitive = object("foxglove.TextPrimitive", "a text label",
                              {{"pose", pose("position")},
                               {"billboard", boolean("always face the camera")},
                               {"font_size", number("size [m], or pixels when scale_invariant")},
                               {"scale_invariant", boolean("font_size in pixels")},
                               {"color", colour},
                               {"text", text("the text")}});
  Json model = object("foxglove.ModelPrimitive", "a 3-D model (not used by these tools)",
                      {{"pose", pose("origin")},
                       {"scale", vector3("scale")},
                       {"color", colour},
                       {"override_color", boolean("use `color` instead of the model's")},
                       {"url", text("where the model is")},
                       {"media_type", text("media type of `data`")},
                       {"data", bytes("the model")}});
  Json keyValue = object("foxglove.KeyValuePair", "a key and its value",
                         {{"key", text("key")}, {"value", text("value")}});
  Json entity = object(
      "foxglove.SceneEntity", "a visual element made of primitives in one frame",
      {{"timestamp", time("time of the entity")},
       {"frame_id", text("frame of reference")},
       {"id", text("identifier; an entity replaces the earlier one with the same id on its topic")},
       {"lifetime", duration("shown this long after `timestamp` (0: until replaced or deleted)")},
       {"frame_locked", boolean("follow `frame_id` as it moves (true) or stay put in the fixed frame (false)")},
       {"metadata", arrayOf(keyValue, "extra key/value pairs")},
       {"arrows", arrayOf(arrow, "arrows")},
       {"cubes", arrayOf(cube, "boxes")},
       {"spheres", arrayOf(sphere, "spheres")},
       {"cylinders", arrayOf(cylinder, "cylinders")},
       {"lines", arrayOf(line, "polylines")},
       {"triangles", arrayOf(triangles, "triangle lists")},
       {"texts", arrayOf(textPrimitive, "labels")},
       {"models", arrayOf(model, "3-D models")}});
  Json deletion = object("foxglove.SceneEntityDeletion", "removes entities shown earlier",
                         {{"timestamp", time("entities older than this are removed")},
                          {"type", enumeration("foxglove.SceneEntityDeletionType", "what to remove",
                                               {{"MATCHING_ID", 0}, {"ALL", 1}})},
                          {"id", text("the entity to remove when type is MATCHING_ID")}});
  return object("foxglove.SceneUpdate", "entities to remove, then entities to add or replace",
                {{"deletions", arrayOf(deletion, "removals, applied first")},
                 {"entities", arrayOf(entity, "entities to add or replace")}});
}

// Not a Foxglove type: process_status_t with its parallel name/value arrays turned into arrays
// of {name, value} objects, so that a Plot panel can pick one by name with a message-path
// filter, e.g. /planner_status.timings[:]{name=="plan_total"}.median_ms.
Json statusView() {
  Json entry = object(nullptr, "one named value", {{"name", text("name")}, {"value", number("value")}});
  Json timing = object(nullptr, "one stage's timing over the last period",
                       {{"name", text("stage")},
                        {"median_ms", number("median [ms] (null: no sample)")},
                        {"max_ms", number("maximum [ms] (null: no sample)")}});
  Json o = object("ucon.StatusView", "a process's health, timings, counters and gauges (from <NAME>_STATUS)",
                  {{"utime", {{"type", "integer"}, {"description", "the node's message time [us]"}}},
                   {"name", text("process")},
                   {"health", enumeration("ucon.Health", "health", {{"OK", 0}, {"WARN", 1}, {"ERROR", 2}})},
                   {"message", text("what is wrong, empty when OK")},
                   {"timings", arrayOf(timing, "per-stage timings")},
                   {"counters", arrayOf(entry, "totals since start")},
                   {"values", arrayOf(entry, "gauges")}});
  return o;
}

}  // namespace

const std::string& foxgloveSchema(const std::string& schema_name) {
  static const std::map<std::string, std::string> kSchemas = {
      {"foxglove.PointCloud", pointCloud().dump()},
      {"foxglove.FrameTransform", frameTransform().dump()},
      {"foxglove.PoseInFrame", poseInFrame().dump()},
      {"foxglove.SceneUpdate", sceneUpdate().dump()},
      {"foxglove.Grid", grid().dump()},
      {"ucon.StatusView", statusView().dump()},
  };
  static const std::string kNone;
  const auto it = kSchemas.find(schema_name);
  return it == kSchemas.end() ? kNone : it->second;
}

}  // namespace foxglove
}  // namespace ucon
