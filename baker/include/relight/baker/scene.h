// A scene as the lighting designer writes it (TOML + OBJ/MTL), in metres,
// world z up. Parsed by LoadScene(); every input error is a SceneError that
// names the file and line.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace relight::baker {

using Vec3 = std::array<double, 3>;
using Rgb = std::array<double, 3>;

// Input error with the place it came from (pbrt's FileLoc idea).
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, int line, const std::string& what)
      : std::runtime_error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                           what),
        file_(file),
        line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

// A planar convex polygon (triangle or quad from an inline quad, a box face
// or an OBJ face), vertices counter-clockwise seen from the lit side.
struct Surface {
  std::string name;               // "floor", "box tall/+x", "sofa.obj:12"
  std::vector<Vec3> corners;      // 3 or 4, planar, convex
  Rgb reflectance{0.5, 0.5, 0.5};  // diffuse, each in [0, 1)
  int line = 0;                    // of its object in the scene file, for messages (0: unknown)
};

enum class LidKind { kIsotropic, kCosPower, kTable, kCGamma, kBeam };

struct PhotometricTable;  // relight/baker/photometric_file.h

// Luminous intensity distribution: rotationally symmetric about the beam axis
// (isotropic, cos^k, table, a zoom optic's beam model (beam_profile.h), and
// photometric files with one C plane), or a
// photometric file's full table over (C, gamma) (kCGamma).
struct Lid {
  LidKind kind = LidKind::kIsotropic;
  double peak_cd = 1000.0;        // isotropic, cos^k, beam: intensity on the axis, candela
  double exponent = 1.0;          // cos^k: k
  double spread_deg = 90.0;       // cos^k: zero beyond this gamma (Dobashi Eq. 11)
  std::vector<double> gamma_deg;  // table: strictly increasing, first 0
  std::vector<double> candela;    // table: same length, >= 0
  // beam (relight/baker/beam_profile.h): peak_cd x f(gamma / (beam_deg / 2)).
  double beam_deg = 0;       // full angle at half peak
  double beam_exponent = 2;  // p of the profile, from the field angle
  double lumens = 0;         // flux, held as the beam zooms
  double zoom_min_deg = 0, zoom_max_deg = 0;  // beam angle range; 0, 0: no zoom
  bool zooms() const { return kind == LidKind::kBeam && zoom_max_deg > 0; }
  // kCGamma: the file's table (shared, read-only). For a file path in messages.
  std::shared_ptr<const PhotometricTable> file;
  std::string file_path;
  // Intensity in candela at angle gamma (degrees) from the axis. Table:
  // linear between control points, 0 below the first and past the last one.
  // kCGamma: the average over C (the axisymmetric part of the beam).
  double Evaluate(double gamma_deg) const;
  // Intensity at photometric angles (C, gamma) in degrees (photometric_file.h);
  // the same as Evaluate(gamma) for the axisymmetric kinds.
  double Evaluate(double c_deg, double gamma_deg) const;
  bool axisymmetric() const { return kind != LidKind::kCGamma; }
};

// bake.h gives the frames: hanging (beam down at rest), standing (beam up),
// wall (beam out of the wall, horizontal, at rest).
enum class MountingKind { kHanging, kStanding, kWall };
enum class DirectModeKind { kExact, kAllInSh };

struct Luminaire {
  std::string name;
  Vec3 position{0, 0, 0};
  MountingKind mounting = MountingKind::kHanging;
  double pan_deg = 0, tilt_deg = 0;  // default aim (see runtime/bake/include/relight/bake/bake.h for the convention)
  double yaw_deg = 0;                // turn of the base about world z (a wall: the way it faces)
  double roll_deg = 0;               // turn about the beam axis, towards increasing C
  double pan_range_deg = 540, tilt_range_deg = 270;  // console 16-bit ranges, centred on 0
  double dimmer = 1.0;               // default, 0..1
  Rgb colour{1, 1, 1};               // default, each 0..1
  int sh_degree = 8;                 // N, 0..16
  // The scene (or --lid-error) set sh_degree; otherwise a zooming beam gets
  // the degree its narrowest angle needs (ChooseZoomDegrees, lid_error.h).
  bool sh_degree_given = false;
  // Sigma factor on the Legendre series (Dobashi Eq. 13). Unset: on for the
  // all-in-SH mode, where ringing would show as bright rings in the direct
  // light; off with the exact direct term, where the SH only carries the
  // indirect light and the undamped (least-squares) series is far more
  // accurate (docs/accuracy.md).
  std::optional<bool> use_sigma;
  Lid lid;
  int line = 0;                      // where it was declared, for messages
};

struct CalcGrid {
  std::string name;
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  // unit, one per point
  int columns = 0, rows = 0;  // a rectangle's layout; 0, 0 for a list
};

struct Camera {
  Vec3 position{0, 0, 0};
  Vec3 target{0, 0, 1};
  double fov_y_deg = 50;
};

struct Scene {
  std::string name;
  std::string path;                 // the TOML file
  double patch_size_m = 0.25;       // target patch edge length for meshing
  std::vector<Surface> surfaces;
  std::vector<Luminaire> luminaires;
  std::vector<CalcGrid> grids;
  Camera camera;
  double white_cd_m2 = 0;           // display white for tone mapping; 0 = choose automatically
};

// Parses a scene file. Relative OBJ paths resolve against the TOML's folder.
// Throws SceneError (file:line: what was expected) on any bad input.
Scene LoadScene(const std::string& toml_path);

}  // namespace relight::baker
