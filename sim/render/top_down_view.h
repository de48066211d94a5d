#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types/image.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// A part of the world to draw: the axis-aligned rectangle [min_m, max_m].
struct TopDownWindow {
  Eigen::Vector2d min_m{0, 0};
  Eigen::Vector2d max_m{0, 0};  // > min_m in x and y
};

struct TopDownOptions {
  int width_px = 900;             // image width; the height follows the view's aspect, [50, 8000]
  double margin_m = 0.5;          // border around the floor
  double section_height_m = 0.5;  // the cut drawn in black (what a laser at this height sees)
  bool draw_places = true;        // named points and areas
  // The part of the world drawn (a crop); none: the floor and its margin.
  std::optional<TopDownWindow> window;
  // The world material whose colour the crowd's people are drawn in; empty or
  // not a material of the world: kPersonRgb.
  std::string people_material;
};

// Where a picture lies in the world: x right, y up in the world; y down in
// the image.
struct TopDownFrame {
  Eigen::Vector2d top_left_m{0, 0};  // the world point at the image's top-left corner
  double px_per_m = 1.0;             // > 0
};

// The legs' cut drawn when the picture's section is not below a person's hip:
// the height of a laser's beam (chosen), m.
inline constexpr double kPeopleLegCutM = 0.5;

// Skin and clothing (chosen): people whose material is not given.
inline constexpr std::array<std::uint8_t, 3> kPersonRgb{214, 120, 60};

// The colours a person is drawn in, all from one base colour.
struct PersonColours {
  std::array<std::uint8_t, 3> body;     // shoulder disc: the base lightened towards white
  std::array<std::uint8_t, 3> outline;  // disc outline and heading tick: the base darkened
  std::array<std::uint8_t, 3> legs;     // the legs' cuts: the base

  static PersonColours From(const std::array<std::uint8_t, 3>& base);
};

// Draws every present person (parked ones not at all): the shoulder disc
// (shape.radius_m) filled light with a dark outline, a heading tick from
// inside the disc to beyond its edge, and both legs as filled discs where the
// plane z = section_height_m cuts them (at kPeopleLegCutM when that plane is
// not below the hip). Later people are drawn over earlier ones.
void DrawPeople(const std::vector<crowd::PersonState>& people, double section_height_m,
                const PersonColours& colours, const TopDownFrame& frame, core::RgbImage* image);

// A polyline drawn over the view (e.g. a body's true trajectory).
struct TopDownTrack {
  std::vector<Eigen::Vector2d> points_m;
  std::array<std::uint8_t, 3> rgb{200, 40, 40};
  double alpha = 1.0;     // opacity in [0, 1]
  double width_px = 1.0;  // line width
  std::string label{};    // its name in a legend (TopDownLegend); empty: not listed
};

// Renders the world seen from above: floor, element footprints in their material
// colours, the section at the beam height outlined (laser-transparent parts in
// light blue), places, bodies, the crowd's present people (DrawPeople) and
// robots at their current poses, and tracks.
core::RgbImage RenderTopDown(const World& world, const std::vector<TopDownTrack>& tracks,
                             const TopDownOptions& options);

// Where RenderTopDown's picture of `world` lies (the window, or the floor and
// its margin), so that more can be drawn over it. Throws like RenderTopDown on
// a bad window.
TopDownFrame TopDownFrameOf(const World& world, const TopDownOptions& options);

// The kinds of thing RenderTopDown draws over the world, for a legend.
enum class TopDownItem {
  kTrack,      // a labelled track: a line of `rgb`, `alpha`, `width_px`
  kBody,       // a body's footprint filled in `rgb`, with a black heading tick
  kPerson,     // a crowd's person: a disc filled `rgb`, outlined in `outline`
  kRobot,      // a robot's footprint filled in `rgb`, with a black heading tick
  kPlace,      // a place's pose: a dot of `rgb` with a direction tick
  kPlaceArea,  // a place's area: `rgb` at `alpha` over the floor
};

struct TopDownLegendItem {
  TopDownItem item = TopDownItem::kTrack;
  std::string label;  // the track's label; "body", "visitor", "robot", "place", "place area"
  std::array<std::uint8_t, 3> rgb{0, 0, 0};
  std::array<std::uint8_t, 3> outline{0, 0, 0};  // kPerson only
  double alpha = 1.0;
  double width_px = 1.0;
};

// What RenderTopDown(world, tracks, options) draws over the world itself, once
// per label, in drawing order: the labelled tracks of at least two points,
// bodies, present people and robots inside the picture (a disc around their
// centre meets it), and with draw_places the places' areas and poses. The
// first of several items with one label (e.g. robots of two materials) names
// them all.
std::vector<TopDownLegendItem> TopDownLegend(const World& world,
                                             const std::vector<TopDownTrack>& tracks,
                                             const TopDownOptions& options);

}  // namespace pavilion::sim
