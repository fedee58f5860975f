#pragma once
// Private DXF text helpers: the header template handed to GDAL's DXF writer, and the XDATA that
// carries segment attributes GDAL's writer has no place for.

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::io_detail {

/// Writes GDAL's default DXF header with $INSUNITS 6 (metres), $MEASUREMENT 1 (metric), layers
/// WALL (colour 7, white/black), GLASS (colour 4, cyan), CLUTTER (8, grey), DOOR (3, green) and
/// ROOMS (5, blue) and the XDATA application GLASSMAP.
void writeDxfHeaderTemplate(const std::filesystem::path& path);

/// Metres per drawing unit declared by the DXF header's $INSUNITS (1 in, 2 ft, 4 mm, 5 cm, 6 m,
/// ...); 0 when the header declares none or "unitless" (0).
double dxfUnitInMetres(const std::filesystem::path& dxf);

/// Checks that an ASCII DXF is a sequence of (group code, value) line pairs with integer group
/// codes in DXF's range (-5..1071), SECTION/ENDSEC, TABLE/ENDTAB and BLOCK/ENDBLK pairs that
/// neither nest nor stay open, and
/// the closing "0 EOF" group;
/// throws Error naming the file and line otherwise. Run before
/// GDAL's DXF driver, which loops for minutes on some misaligned files (GDAL 3.6, found by
/// fuzzing). Binary DXF ("AutoCAD Binary DXF" sentinel) is left to GDAL.
void checkDxfGroupCodes(const std::filesystem::path& dxf);

/// What GDAL's DXF driver does not say about a layer: its state in the LAYER table.
struct DxfLayerState {
  bool frozen = false;  ///< flag 70 bit 1
  bool off = false;     ///< negative colour (62)
};

/// What our own pass over a text DXF finds that GDAL (3.6) does not tell or does not read.
struct DxfScan {
  std::map<std::string, DxfLayerState> layers;     ///< by lower-case layer name
  std::map<std::string, std::string> entity_type;  ///< ENTITIES section: upper-case handle -> entity
                                                   ///< type (block references keep the handle of
                                                   ///< the INSERT or DIMENSION that drew them)
  std::size_t fit_splines = 0;                     ///< SPLINEs given by fit points only (GDAL drops them with an error)
  std::string patched;                             ///< the file with those splines as LWPOLYLINEs through their fit
                                                   ///< points (same handle, layer, paper space); empty when none
};

/// Scans a text DXF (after checkDxfGroupCodes) for layer states, entity types and fit-point splines.
DxfScan scanDxf(const std::filesystem::path& dxf);

/// Why a feature GDAL read from a DXF is not geometry of the building, "" when it is: paper space;
/// drawn by (entity handle -> DIMENSION, LEADER, HATCH, TEXT, ...) or being (subclasses
/// "AcDbEntity:AcDbDimension:...") an annotation entity; on a frozen or off layer.
std::string dxfIgnoreReason(const DxfScan& scan, bool paper_space, std::string_view handle, std::string_view subclasses,
                            std::string_view layer);

/// Appends XDATA (application GLASSMAP: material, thickness, pane_angle, support, evidence) to
/// the i-th line entity of a DXF written by GDAL from map.segments[i]; `extra_lines` line entities
/// of the extra layers (clutter, doors, room outlines) follow them and get none.
void addDxfXData(const std::filesystem::path& dxf, const VectorMap& map, std::size_t extra_lines = 0);

}  // namespace glassmap::io_detail
