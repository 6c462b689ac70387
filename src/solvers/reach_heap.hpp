// Contacts ordered by how soon they can reach a bound of their contact law, for the rate
// path's ratio test (rate_path.cpp): a contact's margin to its bound moves by at most a
// known rate per unit length of the path's motion in α, so a contact whose margin was y at
// arc length s cannot reach the bound before arc length s + y / rate (its `reach`). The
// test then reads exactly only the contacts whose reach the piece's step can attain,
// instead of every contact's force at every event.
#pragma once

#include <functional>
#include <limits>
#include <queue>
#include <vector>

namespace unjam {

class ReachHeap {
 public:
  // Every one of `contacts` contacts absent.
  void Reset(int contacts) {
    version_.assign(static_cast<std::size_t>(contacts), 0);
    present_.assign(static_cast<std::size_t>(contacts), false);
    heap_ = {};
  }

  // (Re)inserts `contact` with this reach; an earlier entry of it no longer counts.
  void Set(int contact, double reach) {
    const auto c = static_cast<std::size_t>(contact);
    ++version_[c];
    present_[c] = true;
    if (reach < std::numeric_limits<double>::infinity()) heap_.push({reach, contact, version_[c]});
  }

  void Remove(int contact) {
    const auto c = static_cast<std::size_t>(contact);
    ++version_[c];
    present_[c] = false;
  }

  // Takes out, in increasing reach, every present contact whose reach is at most limit()
  // (read again after each visit, which may lower it), calls visit(contact) on each and
  // appends it to `taken`. Taken contacts are absent until Set again.
  template <class Limit, class Visit>
  void TakeWithin(const Limit& limit, const Visit& visit, std::vector<int>& taken) {
    while (!heap_.empty()) {
      const Entry top = heap_.top();
      const auto c = static_cast<std::size_t>(top.contact);
      if (!present_[c] || top.version != version_[c]) {
        heap_.pop();
        continue;
      }
      if (top.reach > limit()) return;
      heap_.pop();
      present_[c] = false;
      taken.push_back(top.contact);
      visit(top.contact);
    }
  }

 private:
  struct Entry {
    double reach;
    int contact;
    unsigned version;
    bool operator>(const Entry& o) const {
      return reach > o.reach || (reach == o.reach && contact > o.contact);
    }
  };
  std::vector<unsigned> version_;
  std::vector<bool> present_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap_;
};

}  // namespace unjam
