#include "glassmap/io/labels_raster.hpp"

#include <gdal.h>

#include <cmath>
#include <memory>

#include "gdal_util.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap {
namespace {

struct DatasetCloser {
  void operator()(void* ds) const {
    if (ds) GDALClose(ds);
  }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

// An engineering (local) CRS in metres: QGIS shows the map in place without a geographic datum.
constexpr const char* kLocalCrs = "LOCAL_CS[\"glassmap map frame\",UNIT[\"metre\",1]]";

void setColourTable(GDALRasterBandH band) {
  GDALColorTableH table = GDALCreateColorTable(GPI_RGB);
  auto set = [&](int i, short r, short g, short b) {
    GDALColorEntry e{r, g, b, 255};
    GDALSetColorEntry(table, i, &e);
  };
  for (int i = 0; i < 256; ++i) set(i, 0, 0, 0);
  set(0, 205, 205, 205);
  set(1, 255, 255, 255);
  set(2, 0, 0, 0);
  for (int k = 0; k < 36; ++k) {  // glass: hue by pane angle
    const double h = 6.0 * k / 36.0, f = h - std::floor(h), v = 217.0;
    const short q = static_cast<short>(v * (1 - f)), t = static_cast<short>(v * f), V = static_cast<short>(v);
    switch (static_cast<int>(h)) {
      case 0: set(10 + k, V, t, 0); break;
      case 1: set(10 + k, q, V, 0); break;
      case 2: set(10 + k, 0, V, t); break;
      case 3: set(10 + k, 0, q, V); break;
      case 4: set(10 + k, t, 0, V); break;
      default: set(10 + k, V, 0, q); break;
    }
  }
  GDALSetRasterColorTable(band, table);
  GDALDestroyColorTable(table);
}

}  // namespace

void writeLabelRaster(const std::filesystem::path& tif, const LabelRaster& r) {
  if (r.width <= 0 || r.height <= 0 || r.codes.size() != static_cast<std::size_t>(r.width) * r.height) {
    throw Error("label raster size does not match its width and height", tif.string());
  }
  io_detail::ensureGdalRegistered();
  writeAtomically(tif, [&](const std::filesystem::path& tmp) {
    io_detail::GdalErrorCollector errors;
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    if (!driver) throw Error("GDAL has no GTiff driver", tif.string());
    const char* options[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
    Dataset ds(GDALCreate(driver, tmp.c_str(), r.width, r.height, 1, GDT_Byte, const_cast<char**>(options)));
    if (!ds) throw Error("cannot create GeoTIFF" + errors.suffix(), tif.string());
    const double top = r.origin.y() + r.height * r.resolution;
    double gt[6] = {r.origin.x(), r.resolution, 0.0, top, 0.0, -r.resolution};
    GDALSetGeoTransform(ds.get(), gt);
    GDALSetProjection(ds.get(), kLocalCrs);
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
    GDALSetRasterNoDataValue(band, 0.0);
    setColourTable(band);
    for (int row = 0; row < r.height; ++row) {  // file row 0 = top = grid row height - 1
      const auto* src = &r.codes[static_cast<std::size_t>(r.height - 1 - row) * r.width];
      if (GDALRasterIO(band, GF_Write, 0, row, r.width, 1, const_cast<std::uint8_t*>(src), r.width, 1, GDT_Byte, 0,
                       0) != CE_None) {
        throw Error("cannot write GeoTIFF row" + errors.suffix(), tif.string());
      }
    }
    GDALFlushCache(ds.get());
    ds.reset();
    if (errors.failures() > 0) throw Error("GDAL failed writing GeoTIFF" + errors.suffix(), tif.string());
  });
}

LabelRaster readLabelRaster(const std::filesystem::path& tif) {
  io_detail::ensureGdalRegistered();
  io_detail::GdalErrorCollector errors;
  std::error_code ec;
  if (!std::filesystem::exists(tif, ec)) throw Error("no such file" + io_detail::reason(ec), tif.string());
  Dataset ds(GDALOpen(tif.c_str(), GA_ReadOnly));
  if (!ds) throw Error("cannot open raster" + errors.suffix(), tif.string());
  if (GDALGetRasterCount(ds.get()) != 1) throw Error("expected a single-band raster", tif.string());
  GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
  if (GDALGetRasterDataType(band) != GDT_Byte)
    throw Error("expected Byte (uint8) label codes", tif.string(), 0, "band 1");
  double gt[6];
  if (GDALGetGeoTransform(ds.get(), gt) != CE_None) throw Error("raster has no geotransform", tif.string());
  if (gt[2] != 0.0 || gt[4] != 0.0 || !(gt[1] > 0.0) || std::abs(std::abs(gt[5]) - gt[1]) > 1e-9 * gt[1]) {
    throw Error("expected square, unrotated pixels", tif.string(), 0, "geotransform");
  }
  LabelRaster r;
  r.width = GDALGetRasterXSize(ds.get());
  r.height = GDALGetRasterYSize(ds.get());
  r.resolution = gt[1];
  const bool north_up = gt[5] < 0.0;
  r.origin = Vec2(gt[0], north_up ? gt[3] + r.height * gt[5] : gt[3]);
  // A forged header must not make us allocate gigabytes: 1 G cells is a 50 km square at 5 cm.
  constexpr std::size_t kMaxCells = std::size_t{1} << 30;
  if (r.width <= 0 || r.height <= 0 || static_cast<std::size_t>(r.width) * r.height > kMaxCells)
    throw Error("implausible raster size " + std::to_string(r.width) + " x " + std::to_string(r.height), tif.string());
  r.codes.resize(static_cast<std::size_t>(r.width) * r.height);
  for (int row = 0; row < r.height; ++row) {
    const int grid_row = north_up ? r.height - 1 - row : row;
    if (GDALRasterIO(band, GF_Read, 0, row, r.width, 1, &r.codes[static_cast<std::size_t>(grid_row) * r.width], r.width,
                     1, GDT_Byte, 0, 0) != CE_None) {
      throw Error("cannot read raster row " + std::to_string(row) + errors.suffix(), tif.string());
    }
  }
  return r;
}

}  // namespace glassmap
