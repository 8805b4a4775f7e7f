#pragma once
// A least-recently-used cache bounded by bytes (COLMAP's cache_size), for images and depth
// maps that several reference images share.
#include <cstddef>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <utility>

namespace mpmvs {

template <typename Key, typename Value>
class LruCache {
 public:
  using Loader = std::function<Value(const Key&)>;
  using Sizer = std::function<size_t(const Value&)>;

  LruCache(size_t max_bytes, Loader loader, Sizer sizer)
      : max_bytes_(max_bytes), loader_(std::move(loader)), sizer_(std::move(sizer)) {}

  // Shared so that an entry evicted while in use stays alive for its user.
  std::shared_ptr<const Value> Get(const Key& key) {
    auto it = index_.find(key);
    if (it != index_.end()) {
      entries_.splice(entries_.begin(), entries_, it->second);
      return it->second->second;
    }
    auto value = std::make_shared<const Value>(loader_(key));
    const size_t bytes = sizer_(*value);
    entries_.emplace_front(key, value);
    index_[key] = entries_.begin();
    bytes_ += bytes;
    // Keep at least the newest entry even when it alone exceeds the budget.
    while (bytes_ > max_bytes_ && entries_.size() > 1) {
      auto& last = entries_.back();
      bytes_ -= sizer_(*last.second);
      index_.erase(last.first);
      entries_.pop_back();
    }
    return value;
  }

  void Erase(const Key& key) {
    auto it = index_.find(key);
    if (it == index_.end()) return;
    bytes_ -= sizer_(*it->second->second);
    entries_.erase(it->second);
    index_.erase(it);
  }

  size_t Bytes() const { return bytes_; }
  size_t Size() const { return entries_.size(); }

 private:
  using Entry = std::pair<Key, std::shared_ptr<const Value>>;
  size_t max_bytes_;
  Loader loader_;
  Sizer sizer_;
  size_t bytes_ = 0;
  std::list<Entry> entries_;
  std::map<Key, typename std::list<Entry>::iterator> index_;
};

}  // namespace mpmvs
