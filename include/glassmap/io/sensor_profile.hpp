#pragma once
/// Sensor profiles on disk (YAML, written by `glassmap calibrate`, read by `--sensor`) and the
/// calibration chart (PNG): the fitted direct-return lobe over the measured fraction per angle bin.

#include <filesystem>
#include <vector>

#include "glassmap/core/sensor_profile.hpp"

namespace glassmap {

/// Writes the profile as YAML: one key per parameter (value, and `<key>_se` where fitted), plus
/// `fitted:` listing what was estimated and `source`. Atomic.
void writeSensorProfile(const std::filesystem::path& path, const SensorProfile& profile);

/// Reads a profile written by writeSensorProfile (or by hand: any subset of the keys; missing
/// ones keep the defaults). Throws Error naming the file, line and key for a bad or implausible
/// value (sigma <= 0, a probability outside [0, 1], a negative rate).
SensorProfile readSensorProfile(const std::filesystem::path& path);

/// Draws the calibration chart as PNG: per bin the measured direct-return fraction (dots, with a
/// binomial 95% interval) and the fitted lobe; the reflected fraction and its fit in a second
/// colour. Atomic.
void renderCalibrationChart(const std::filesystem::path& path, const SensorProfile& profile,
                            const std::vector<GlassAngleBin>& bins);

}  // namespace glassmap
