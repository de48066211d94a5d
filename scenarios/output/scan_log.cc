#include "scenarios/output/scan_log.h"

#include <bit>
#include <cstring>
#include <iterator>
#include <stdexcept>

namespace pavilion::scenarios {
namespace {

static_assert(std::endian::native == std::endian::little, "scan logs are little-endian");

constexpr char kMagic[8] = {'P', 'A', 'V', 'S', 'C', 'A', 'N', '1'};
constexpr std::uint8_t kValid = 1;
constexpr std::uint8_t kReflector = 2;

template <typename T>
void Put(std::string* out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out->append(bytes, sizeof(T));
}

void PutString(std::string* out, const std::string& s) {
  Put<std::uint16_t>(out, static_cast<std::uint16_t>(s.size()));
  out->append(s);
}

class Cursor {
 public:
  Cursor(const std::string& path, const std::string& data, std::size_t start)
      : path_(path), data_(data), pos_(start) {}
  template <typename T>
  T Get() {
    Need(sizeof(T));
    T value;
    std::memcpy(&value, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  std::string GetString() {
    const auto n = Get<std::uint16_t>();
    Need(n);
    std::string s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  bool done() const { return pos_ == data_.size(); }
  std::size_t pos() const { return pos_; }

 private:
  void Need(std::size_t n) const {
    if (pos_ + n > data_.size()) {
      throw std::runtime_error(path_ + ": truncated scan log at byte " + std::to_string(pos_));
    }
  }
  const std::string& path_;
  const std::string& data_;
  std::size_t pos_;
};

}  // namespace

ScanLogWriter::ScanLogWriter(const std::string& path, const std::vector<std::string>& element_ids)
    : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw std::runtime_error(path + ": cannot open for writing");
  buffer_.append(kMagic, sizeof kMagic);
  Put<std::uint32_t>(&buffer_, static_cast<std::uint32_t>(element_ids.size()));
  for (const std::string& id : element_ids) PutString(&buffer_, id);
}

void ScanLogWriter::Append(const std::string& robot, const core::LaserScan& scan,
                           const core::LaserScanTruth& truth) {
  std::string record;
  PutString(&record, robot);
  PutString(&record, scan.sensor_id);
  Put<double>(&record, scan.stamp_s);
  Put<double>(&record, scan.max_range_m);
  Put<double>(&record, scan.robot_from_sensor.x_m);
  Put<double>(&record, scan.robot_from_sensor.y_m);
  Put<double>(&record, scan.robot_from_sensor.theta_rad);
  const auto n = static_cast<std::uint32_t>(scan.readings.size());
  Put<std::uint32_t>(&record, n);
  for (const core::LaserReading& r : scan.readings) {
    Put<float>(&record, static_cast<float>(r.bearing_rad));
    Put<float>(&record, static_cast<float>(r.range_m));
    Put<float>(&record, static_cast<float>(r.time_offset_s));
    Put<std::uint8_t>(&record, (r.valid ? kValid : 0) | (r.reflector ? kReflector : 0));
  }
  const bool has_truth = truth.true_range_m.size() == n;
  Put<std::uint8_t>(&record, has_truth ? 1 : 0);
  for (std::uint32_t i = 0; has_truth && i < n; ++i) {
    Put<double>(&record, truth.world_from_sensor[i].x_m);
    Put<double>(&record, truth.world_from_sensor[i].y_m);
    Put<float>(&record, static_cast<float>(truth.world_from_sensor[i].theta_rad));
    Put<float>(&record, static_cast<float>(truth.true_range_m[i]));
    Put<std::int32_t>(&record, truth.element[i]);
  }
  Put<std::uint32_t>(&buffer_, static_cast<std::uint32_t>(record.size()));
  buffer_ += record;
  ++scans_;
  if (buffer_.size() > (1u << 20)) {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }
}

void ScanLogWriter::Close() {
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
  out_.flush();
  if (!out_) throw std::runtime_error(path_ + ": write failed");
  out_.close();
}

ScanLog ReadScanLog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open scan log");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() < sizeof kMagic || std::memcmp(data.data(), kMagic, sizeof kMagic) != 0) {
    throw std::runtime_error(path + ": not a Pavilion scan log (magic PAVSCAN1 missing)");
  }
  Cursor c(path, data, sizeof kMagic);
  ScanLog log;
  const auto elements = c.Get<std::uint32_t>();
  for (std::uint32_t i = 0; i < elements; ++i) log.element_ids.push_back(c.GetString());
  while (!c.done()) {
    const std::size_t start = c.pos();
    const auto bytes = c.Get<std::uint32_t>();
    ScanLogRecord rec;
    rec.robot = c.GetString();
    rec.scan.sensor_id = c.GetString();
    rec.scan.stamp_s = c.Get<double>();
    rec.scan.max_range_m = c.Get<double>();
    rec.scan.robot_from_sensor.x_m = c.Get<double>();
    rec.scan.robot_from_sensor.y_m = c.Get<double>();
    rec.scan.robot_from_sensor.theta_rad = c.Get<double>();
    const auto n = c.Get<std::uint32_t>();
    rec.scan.readings.resize(n);
    for (core::LaserReading& r : rec.scan.readings) {
      r.bearing_rad = c.Get<float>();
      r.range_m = c.Get<float>();
      r.time_offset_s = c.Get<float>();
      const auto flags = c.Get<std::uint8_t>();
      r.valid = (flags & kValid) != 0;
      r.reflector = (flags & kReflector) != 0;
    }
    if (c.Get<std::uint8_t>() != 0) {
      for (std::uint32_t i = 0; i < n; ++i) {
        core::Pose2 p;
        p.x_m = c.Get<double>();
        p.y_m = c.Get<double>();
        p.theta_rad = c.Get<float>();
        rec.truth.world_from_sensor.push_back(p);
        rec.truth.true_range_m.push_back(c.Get<float>());
        rec.truth.element.push_back(c.Get<std::int32_t>());
      }
    }
    if (c.pos() - start != bytes + sizeof(std::uint32_t)) {
      throw std::runtime_error(path + ": malformed scan record at byte " + std::to_string(start));
    }
    log.records.push_back(std::move(rec));
  }
  return log;
}

}  // namespace pavilion::scenarios
