#pragma once
/// CAD layer names → materials: user rules, then a built-in table after the common standards
/// (AIA / US National CAD Standard A-WALL, A-GLAZ, A-DOOR, ...), and the report of what a
/// floorplan reader read as what.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace glassmap {

/// What the lines of a layer are: wall, glass, or not part of the building's surfaces.
enum class LayerRole { Wall, Glass, Ignore };

/// "wall", "glass", "ignore".
std::string_view toString(LayerRole role);

/// Layers whose name matches `pattern` (glob: * any run, ? one character; case-insensitive;
/// an xref prefix "XREF|" is dropped before matching) take `role`.
struct LayerRule {
  LayerRole role = LayerRole::Wall;
  std::string pattern;
  std::string why;  ///< what a report says about it ("ignored: annotation" ...); empty: role name
};

/// Parses "glass=A-GLAZ*,*WINDOW*;wall=A-WALL*;ignore=A-FURN*" (roles wall, glass, ignore;
/// patterns comma-separated, rules ';'-separated). Throws Error naming `field` otherwise.
std::vector<LayerRule> parseLayerRules(const std::string& text, const std::string& field = "layers");

/// The built-in table, first match wins (see floorplan_layers.cpp for the reasons).
const std::vector<LayerRule>& standardLayerRules();

/// True when `name` matches the glob `pattern` (case-insensitive).
bool globMatch(std::string_view pattern, std::string_view name);

/// How one layer name was classified.
struct LayerDecision {
  LayerRole role = LayerRole::Wall;
  std::string why;     ///< "--layers glass=A-GLAZ*", "standard *GLAZ*", "unknown layer name"
  bool known = false;  ///< a rule matched (false: unknown name, read as wall)
};

/// User rules first, then (when `standard`) the built-in table; unknown names are walls.
LayerDecision classifyLayer(std::string_view name, const std::vector<LayerRule>& user, bool standard = true);

/// One row of the read report: features of one source layer with one outcome.
struct LayerReadCount {
  std::string layer;         ///< CAD layer (DXF `Layer` field) or OGR layer name
  std::string outcome;       ///< "wall", "glass" or "ignored"
  std::string why;           ///< rule or reason: "standard A-WALL*", "dimension", "frozen layer", ...
  std::size_t features = 0;  ///< source features
  std::size_t segments = 0;  ///< segments read (0 when ignored)
};

/// What readFloorplan read as what, and what a user should know about it.
struct FloorplanReadReport {
  std::vector<LayerReadCount> rows;   ///< in order of first appearance
  std::vector<std::string> warnings;  ///< doubtful results (unknown layer names, no walls, ...)
  std::vector<std::string> notes;     ///< conversions made (fit-point splines as polylines, ...)
  bool by_layer_names = false;        ///< some material came from layer names or a filter
};

/// The report as text lines for stderr: a table of rows, then notes and warnings.
std::string formatReadReport(const FloorplanReadReport& report);

}  // namespace glassmap
