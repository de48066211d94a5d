#include "sim/render/top_down_view.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sim/world/wall_geometry.h"

namespace pavilion::sim {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

Rgb ToRgb(const std::array<double, 4>& rgba) {
  auto c = [](double v) {
    return static_cast<std::uint8_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5);
  };
  return {c(rgba[0]), c(rgba[1]), c(rgba[2])};
}

// Pixel drawing on an RgbImage with a metric world-to-pixel mapping.
class Canvas {
 public:
  Canvas(core::RgbImage* image, Eigen::Vector2d origin_m, double px_per_m)
      : image_(image), origin_m_(origin_m), scale_(px_per_m) {}

  Eigen::Vector2d ToPx(const Eigen::Vector2d& p) const {
    return {(p.x() - origin_m_.x()) * scale_, (origin_m_.y() - p.y()) * scale_};
  }
  double scale() const { return scale_; }

  void Put(int x, int y, const Rgb& c, double alpha = 1.0) {
    if (x < 0 || y < 0 || x >= image_->width || y >= image_->height) return;
    std::uint8_t* p = &image_->pixels[(static_cast<std::size_t>(y) * image_->width + x) * 3];
    for (int k = 0; k < 3; ++k) {
      p[k] = static_cast<std::uint8_t>(std::lround(alpha * c[k] + (1.0 - alpha) * p[k]));
    }
  }

  // Even-odd scanline fill of a polygon given in metres.
  void FillPolygon(const std::vector<Eigen::Vector2d>& poly_m, const Rgb& c, double alpha = 1.0) {
    std::vector<Eigen::Vector2d> p;
    for (const auto& q : poly_m) p.push_back(ToPx(q));
    double ymin = 1e18, ymax = -1e18;
    for (const auto& q : p) {
      ymin = std::min(ymin, q.y());
      ymax = std::max(ymax, q.y());
    }
    const int y0 = std::max(0, static_cast<int>(std::floor(ymin)));
    const int y1 = std::min(image_->height - 1, static_cast<int>(std::ceil(ymax)));
    std::vector<double> xs;
    for (int y = y0; y <= y1; ++y) {
      const double yc = y + 0.5;
      xs.clear();
      for (std::size_t i = 0, n = p.size(); i < n; ++i) {
        const auto& a = p[i];
        const auto& b = p[(i + 1) % n];
        if ((a.y() > yc) != (b.y() > yc))
          xs.push_back(a.x() + (yc - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        for (int x = static_cast<int>(std::ceil(xs[k] - 0.5));
             x <= static_cast<int>(std::floor(xs[k + 1] - 0.5)); ++x) {
          Put(x, y, c, alpha);
        }
      }
    }
  }

  void FillCircle(const Eigen::Vector2d& centre_m, double radius_m, const Rgb& c,
                  double alpha = 1.0) {
    const Eigen::Vector2d q = ToPx(centre_m);
    const double r = std::max(radius_m * scale_, 0.7);
    for (int y = static_cast<int>(q.y() - r); y <= static_cast<int>(q.y() + r) + 1; ++y) {
      for (int x = static_cast<int>(q.x() - r); x <= static_cast<int>(q.x() + r) + 1; ++x) {
        const double dx = x + 0.5 - q.x(), dy = y + 0.5 - q.y();
        if (dx * dx + dy * dy <= r * r) Put(x, y, c, alpha);
      }
    }
  }

  // A line of the given width in pixels, sampled densely.
  void Line(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m, const Rgb& c, double width_px,
            double alpha = 1.0) {
    const Eigen::Vector2d a = ToPx(a_m), b = ToPx(b_m);
    const double len = (b - a).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(len * 2.0)));
    const double h = 0.5 * width_px;
    for (int i = 0; i <= steps; ++i) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / steps);
      for (int y = static_cast<int>(std::floor(p.y() - h));
           y <= static_cast<int>(std::floor(p.y() + h)); ++y) {
        for (int x = static_cast<int>(std::floor(p.x() - h));
             x <= static_cast<int>(std::floor(p.x() + h)); ++x) {
          Put(x, y, c, alpha);
        }
      }
    }
  }

  void Circle(const Eigen::Vector2d& centre_m, double radius_m, const Rgb& c, double width_px) {
    const int n = std::max(12, static_cast<int>(radius_m * scale_ * 2.0));
    for (int i = 0; i < n; ++i) {
      const double t0 = 2.0 * std::numbers::pi * i / n, t1 = 2.0 * std::numbers::pi * (i + 1) / n;
      Line(centre_m + radius_m * Eigen::Vector2d(std::cos(t0), std::sin(t0)),
           centre_m + radius_m * Eigen::Vector2d(std::cos(t1), std::sin(t1)), c, width_px);
    }
  }

 private:
  core::RgbImage* image_;
  Eigen::Vector2d origin_m_;  // world point at the image's top-left corner
  double scale_;
};

constexpr Rgb kSectionColour{20, 20, 20};
constexpr Rgb kTransparentColour{90, 170, 230};
constexpr Rgb kPlaceColour{40, 150, 60};

Rgb MaterialRgb(const WorldDescription& d, const std::string& material) {
  return ToRgb(d.MaterialNamed(material).rgba);
}

double MaterialAlpha(const WorldDescription& d, const std::string& material) {
  return d.MaterialNamed(material).rgba[3];
}

// The floor, place areas and static elements of the description, filled.
void DrawStatics(const WorldDescription& d, const TopDownOptions& options, Canvas* canvas) {
  const auto colour = [&](const std::string& material) { return MaterialRgb(d, material); };
  const auto alpha = [&](const std::string& material) { return MaterialAlpha(d, material); };
  canvas->FillPolygon({d.floor.min_m,
                       {d.floor.max_m.x(), d.floor.min_m.y()},
                       d.floor.max_m,
                       {d.floor.min_m.x(), d.floor.max_m.y()}},
                      colour(d.floor.material));
  for (const auto& [name, place] : d.places) {
    if (options.draw_places && place.area) canvas->FillPolygon(*place.area, kPlaceColour, 0.15);
  }
  for (const Wall& w : d.walls) {
    for (const Quad& q : WallFootprint(w))
      canvas->FillPolygon({q.begin(), q.end()}, colour(w.material), alpha(w.material));
  }
  for (const Box& b : d.boxes) {
    const Quad q = BoxFootprint(b);
    canvas->FillPolygon({q.begin(), q.end()}, colour(b.material), alpha(b.material));
  }
  for (const Door& door : d.doors) {
    const Quad q = BoxFootprint(door.AsBox());
    canvas->FillPolygon({q.begin(), q.end()}, colour(door.material), alpha(door.material));
  }
  for (const Cylinder& c : d.cylinders) {
    canvas->FillCircle(c.position_m, c.radius_m, colour(c.material), alpha(c.material));
  }
}

// The cut of the static elements at beam height: what a laser there can meet.
void DrawStaticSection(const World& world, const TopDownOptions& options, Canvas* canvas) {
  const core::PlanarSection section = world.SectionAt(options.section_height_m);
  for (const auto& s : section.segments) {
    const bool glass = section.elements[s.element].laser == core::LaserResponse::kTransparent;
    if (section.elements[s.element].dynamic) continue;
    canvas->Line(s.a_m, s.b_m, glass ? kTransparentColour : kSectionColour, 1.5);
  }
  for (const auto& c : section.circles) {
    if (section.elements[c.element].dynamic) continue;
    canvas->Circle(c.center_m, c.radius_m, kSectionColour, 1.5);
  }
}

// Every body at its pose, with a heading tick.
void DrawBodies(const World& world, Canvas* canvas) {
  const WorldDescription& d = world.description();
  for (int b = 0; b < world.body_count(); ++b) {
    const BodySpec& spec = world.body_spec(b);
    const BodyState state = world.body_state(b);
    const Rgb c = MaterialRgb(d, spec.material);
    if (spec.shape.type == BodyShapeType::kBox) {
      Box box;
      box.pose = state.pose;
      box.size_m = spec.shape.box_size_m;
      const Quad q = BoxFootprint(box);
      canvas->FillPolygon({q.begin(), q.end()}, c);
    } else {
      canvas->FillCircle(state.pose.translation(), spec.shape.radius_m, c);
    }
    const double r = spec.shape.type == BodyShapeType::kBox ? 0.5 * spec.shape.box_size_m.x()
                                                            : spec.shape.radius_m;
    const Eigen::Vector2d heading(std::cos(state.pose.theta_rad), std::sin(state.pose.theta_rad));
    canvas->Line(state.pose.translation(), state.pose.translation() + r * heading, {0, 0, 0}, 1.0);
  }
}

// Every robot's footprint and attachments at its true pose, with a heading tick.
void DrawRobots(const World& world, Canvas* canvas) {
  const WorldDescription& d = world.description();
  for (int r = 0; r < world.robot_count(); ++r) {
    const RobotDescription& model = world.robot_model(r);
    const RobotState state = world.robot_state(r);
    std::vector<Eigen::Vector2d> outline;
    for (const Eigen::Vector2d& p : model.footprint_m) outline.push_back(state.pose * p);
    canvas->FillPolygon(outline, MaterialRgb(d, model.material));
    for (const MarkerSpec& a : model.markers) {
      canvas->FillCircle(state.pose * a.position_m, a.radius_m, MaterialRgb(d, a.material));
    }
    double reach = 0.0;
    for (const Eigen::Vector2d& p : model.footprint_m) reach = std::max(reach, p.x());
    const Eigen::Vector2d heading(std::cos(state.pose.theta_rad), std::sin(state.pose.theta_rad));
    canvas->Line(state.pose.translation(), state.pose.translation() + reach * heading, {0, 0, 0},
                 1.5);
  }
}

// A person's heading tick runs along the heading from this fraction of the
// shoulder radius (inside the disc) to the next (beyond its edge); chosen.
constexpr double kTickFromRadii = 0.5;
constexpr double kTickToRadii = 1.45;
constexpr double kTickWidthPx = 1.5;
constexpr double kOutlineWidthPx = 1.0;
// PersonColours: the disc is the base this far towards white, the outline
// the base scaled by kOutlineShade (chosen for contrast on a light floor).
constexpr double kBodyLighten = 0.6;
constexpr double kOutlineShade = 0.5;

// A person's colour: the material's, or kPersonRgb.
Rgb PeopleRgb(const WorldDescription& d, const TopDownOptions& options) {
  if (options.people_material.empty() || !d.materials.contains(options.people_material)) {
    return kPersonRgb;
  }
  return MaterialRgb(d, options.people_material);
}

// The places' poses as dots with a direction tick.
void DrawPlacePoses(const WorldDescription& d, const TopDownOptions& options, double scale,
                    Canvas* canvas) {
  for (const auto& [name, place] : d.places) {
    if (!options.draw_places || !place.pose) continue;
    const Eigen::Vector2d p = place.pose->translation();
    canvas->FillCircle(p, 3.0 / scale, kPlaceColour);
    const Eigen::Vector2d dir(std::cos(place.pose->theta_rad), std::sin(place.pose->theta_rad));
    canvas->Line(p, p + (10.0 / scale) * dir, kPlaceColour, 1.0);
  }
}

// The world rectangle [lo, hi] the picture covers.
void PictureArea(const World& world, const TopDownOptions& options, Eigen::Vector2d* lo,
                 Eigen::Vector2d* hi) {
  const WorldDescription& d = world.description();
  *lo = d.floor.min_m.array() - options.margin_m;
  *hi = d.floor.max_m.array() + options.margin_m;
  if (options.window) {
    *lo = options.window->min_m;
    *hi = options.window->max_m;
    if (!lo->allFinite() || !hi->allFinite() || !(hi->x() > lo->x()) || !(hi->y() > lo->y())) {
      throw std::invalid_argument("TopDownOptions.window: max_m must exceed min_m in x and y");
    }
  }
}

int PictureWidth(const TopDownOptions& options) { return std::clamp(options.width_px, 50, 8000); }

// Whether a disc of radius r around p meets the rectangle [lo, hi].
bool Meets(const Eigen::Vector2d& p, double r, const Eigen::Vector2d& lo,
           const Eigen::Vector2d& hi) {
  return p.x() + r >= lo.x() && p.x() - r <= hi.x() && p.y() + r >= lo.y() && p.y() - r <= hi.y();
}

// Adds `item` unless its label is listed already.
void AddOnce(TopDownLegendItem item, std::vector<TopDownLegendItem>* out) {
  for (const TopDownLegendItem& i : *out) {
    if (i.label == item.label) return;
  }
  out->push_back(std::move(item));
}

// The bodies', people's and robots' items: those inside [lo, hi].
void AddMovingItems(const World& world, const TopDownOptions& options, const Eigen::Vector2d& lo,
                    const Eigen::Vector2d& hi, std::vector<TopDownLegendItem>* out) {
  const WorldDescription& d = world.description();
  for (int b = 0; b < world.body_count(); ++b) {
    const BodySpec& spec = world.body_spec(b);
    const double reach = spec.shape.type == BodyShapeType::kBox
                             ? 0.5 * spec.shape.box_size_m.head<2>().norm()
                             : spec.shape.radius_m;
    if (Meets(world.body_state(b).pose.translation(), reach, lo, hi)) {
      AddOnce({TopDownItem::kBody, "body", MaterialRgb(d, spec.material)}, out);
    }
  }
  if (const crowd::Crowd* crowd = world.crowd()) {
    const PersonColours colours = PersonColours::From(PeopleRgb(d, options));
    for (const crowd::PersonState& p : crowd->people()) {
      if (p.present && Meets(p.position_m, kTickToRadii * p.shape.radius_m, lo, hi)) {
        AddOnce({TopDownItem::kPerson, "visitor", colours.body, colours.outline}, out);
      }
    }
  }
  for (int r = 0; r < world.robot_count(); ++r) {
    const RobotDescription& model = world.robot_model(r);
    double reach = 0.0;
    for (const Eigen::Vector2d& p : model.footprint_m) reach = std::max(reach, p.norm());
    if (Meets(world.robot_state(r).pose.translation(), reach, lo, hi)) {
      AddOnce({TopDownItem::kRobot, "robot", MaterialRgb(d, model.material)}, out);
    }
  }
}

}  // namespace

PersonColours PersonColours::From(const std::array<std::uint8_t, 3>& base) {
  PersonColours c{base, base, base};
  for (int k = 0; k < 3; ++k) {
    c.body[k] = static_cast<std::uint8_t>(std::lround(base[k] + kBodyLighten * (255 - base[k])));
    c.outline[k] = static_cast<std::uint8_t>(std::lround(kOutlineShade * base[k]));
  }
  return c;
}

void DrawPeople(const std::vector<crowd::PersonState>& people, double section_height_m,
                const PersonColours& colours, const TopDownFrame& frame, core::RgbImage* image) {
  if (!(frame.px_per_m > 0.0) || !std::isfinite(frame.px_per_m)) {
    throw std::invalid_argument("TopDownFrame.px_per_m must be finite and > 0");
  }
  Canvas canvas(image, frame.top_left_m, frame.px_per_m);
  for (const crowd::PersonState& p : people) {
    if (!p.present) continue;
    const double r = p.shape.radius_m;
    const Eigen::Vector2d c = canvas.ToPx(p.position_m);
    // Beyond every part: the tick, and the legs at their widest stride.
    const double reach_m =
        std::max(kTickToRadii * r,
                 p.shape.hip_half_width_m + std::abs(p.gait.swing_m) + p.shape.leg_radius_m);
    const double reach_px = reach_m * frame.px_per_m + kTickWidthPx;
    if (c.x() + reach_px < 0 || c.y() + reach_px < 0 || c.x() - reach_px > image->width ||
        c.y() - reach_px > image->height) {
      continue;  // wholly outside the picture
    }
    canvas.FillCircle(p.position_m, r, colours.body);
    canvas.Circle(p.position_m, r, colours.outline, kOutlineWidthPx);
    const double cut_m =
        section_height_m < p.shape.hip_height_m ? section_height_m : kPeopleLegCutM;
    for (const Eigen::Vector2d& leg : p.LegCentres(cut_m)) {
      canvas.FillCircle(leg, p.shape.leg_radius_m, colours.legs);
    }
    const Eigen::Vector2d forward(std::cos(p.heading_rad), std::sin(p.heading_rad));
    canvas.Line(p.position_m + kTickFromRadii * r * forward,
                p.position_m + kTickToRadii * r * forward, colours.outline, kTickWidthPx);
  }
}

TopDownFrame TopDownFrameOf(const World& world, const TopDownOptions& options) {
  Eigen::Vector2d lo, hi;
  PictureArea(world, options, &lo, &hi);
  return {{lo.x(), hi.y()}, PictureWidth(options) / (hi.x() - lo.x())};
}

core::RgbImage RenderTopDown(const World& world, const std::vector<TopDownTrack>& tracks,
                             const TopDownOptions& options) {
  const WorldDescription& d = world.description();
  Eigen::Vector2d lo, hi;
  PictureArea(world, options, &lo, &hi);
  const int width = PictureWidth(options);
  const double scale = width / (hi.x() - lo.x());
  const int height = std::max(1, static_cast<int>(std::lround((hi.y() - lo.y()) * scale)));
  core::RgbImage image(width, height, 250, 250, 250);
  Canvas canvas(&image, {lo.x(), hi.y()}, scale);
  DrawStatics(d, options, &canvas);
  DrawStaticSection(world, options, &canvas);
  for (const auto& track : tracks) {
    for (std::size_t i = 1; i < track.points_m.size(); ++i) {
      canvas.Line(track.points_m[i - 1], track.points_m[i], track.rgb, track.width_px, track.alpha);
    }
  }
  DrawBodies(world, &canvas);
  if (const crowd::Crowd* crowd = world.crowd()) {
    DrawPeople(crowd->people(), options.section_height_m,
               PersonColours::From(PeopleRgb(d, options)), {{lo.x(), hi.y()}, scale}, &image);
  }
  DrawRobots(world, &canvas);
  DrawPlacePoses(d, options, scale, &canvas);
  return image;
}

std::vector<TopDownLegendItem> TopDownLegend(const World& world,
                                             const std::vector<TopDownTrack>& tracks,
                                             const TopDownOptions& options) {
  const WorldDescription& d = world.description();
  Eigen::Vector2d lo, hi;
  PictureArea(world, options, &lo, &hi);
  std::vector<TopDownLegendItem> out;
  if (options.draw_places) {
    for (const auto& [name, place] : d.places) {
      if (place.area)
        AddOnce({TopDownItem::kPlaceArea, "place area", kPlaceColour, {}, 0.15}, &out);
    }
  }
  for (const TopDownTrack& t : tracks) {
    if (t.label.empty() || t.points_m.size() < 2) continue;
    AddOnce({TopDownItem::kTrack, t.label, t.rgb, {}, t.alpha, t.width_px}, &out);
  }
  AddMovingItems(world, options, lo, hi, &out);
  if (options.draw_places) {
    for (const auto& [name, place] : d.places) {
      if (place.pose) AddOnce({TopDownItem::kPlace, "place", kPlaceColour}, &out);
    }
  }
  return out;
}

}  // namespace pavilion::sim
