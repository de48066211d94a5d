#pragma once

// A bounded record of a long sequence for pictures: keeps every item until
// `capacity` are held, then every second one of those and from then on every
// second item arriving (the stride doubles each time it fills). Memory stays
// O(capacity) however long the run; the kept items are evenly spaced in the
// sequence and depend only on it (deterministic). The last item added is
// always available (last()).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace pavilion::scenarios {

template <typename T>
class StrideBuffer {
 public:
  explicit StrideBuffer(std::size_t capacity = 4096) : capacity_(capacity < 2 ? 2 : capacity) {}

  void Add(T item) {
    if (count_++ % stride_ == 0) {
      if (items_.size() == capacity_) Thin();
      if ((count_ - 1) % stride_ == 0) items_.push_back(item);
    }
    last_ = std::move(item);
  }

  // The kept items in order (every stride()-th from the first).
  const std::vector<T>& items() const { return items_; }
  // The kept items and the last one added when it was not kept.
  std::vector<T> items_and_last() const {
    std::vector<T> out = items_;
    if (count_ > 0 && (count_ - 1) % stride_ != 0) out.push_back(*last_);
    return out;
  }
  const T& last() const { return *last_; }       // only when !empty()
  std::int64_t count() const { return count_; }  // every Add() so far
  std::int64_t stride() const { return stride_; }
  bool empty() const { return count_ == 0; }

 private:
  void Thin() {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < items_.size(); i += 2) items_[kept++] = std::move(items_[i]);
    items_.resize(kept);
    stride_ *= 2;
  }

  std::size_t capacity_;
  std::vector<T> items_;
  std::optional<T> last_;
  std::int64_t count_ = 0;
  std::int64_t stride_ = 1;
};

}  // namespace pavilion::scenarios
