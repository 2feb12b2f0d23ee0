#pragma once
/// @file mot_challenge.hpp
/// MOTChallenge text files (`frame,id,x,y,w,h,conf,...`; 1-based frames, x/y the top-left
/// corner) parsed from text, and their CLEAR-MOT evaluation by box IoU. Reading the files is
/// the caller's job. The confidence column is kept but never filters rows (it may be -1).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ucon/mot/clear_mot.hpp"

namespace ucon {
namespace mot {

/// Boxes per frame number, in file order within a frame.
using MotFrames = std::map<int64_t, std::vector<Box>>;

/// Parses MOTChallenge text: one box per line, fields separated by commas and/or whitespace,
/// at least 6 fields (frame, id, x, y, w, h); extra fields are ignored. Blank lines are
/// skipped. On a malformed line (too few fields, a field that is not a number, a non-finite
/// value, a negative width or height, a frame < 1) returns nullopt and sets `error`
/// to "<source>:<line>: <what>".
std::optional<MotFrames> parseMotChallenge(const std::string& text, const std::string& source,
                                           std::string* error);

/// Runs CLEAR-MOT over every frame present in either file (in increasing frame order),
/// matching boxes by 1 - IoU with pairs below `min_iou` forbidden.
ClearMotSummary evaluateBoxes(const MotFrames& ground_truth, const MotFrames& predictions,
                              double min_iou);

}  // namespace mot
}  // namespace ucon
