// Rectangles packed into square pages shelf by shelf: a rectangle goes on the lowest shelf of
// the page that is tall enough and has room left, else on a new shelf above the others. Groups
// that must share a page (a box's six sides) are placed together or not at all.
#pragma once

#include <optional>
#include <vector>

#include <glm/vec2.hpp>

namespace farfield {

class ShelfPacker {
 public:
  // `gutter` texels are left free right of and above every rectangle.
  ShelfPacker(int page_px, int gutter) : page_(page_px), gutter_(gutter) {}

  int page() const { return page_index_; }
  // Starts an empty page.
  void next_page() {
    ++page_index_;
    shelves_.clear();
    top_ = 0;
  }
  // Where each rectangle goes on the current page, or none (and the page unchanged) where
  // they do not all fit.
  std::optional<std::vector<glm::ivec2>> place(const std::vector<glm::ivec2>& sizes) {
    const std::vector<Shelf> shelves = shelves_;
    const int top = top_;
    std::vector<glm::ivec2> at;
    for (const glm::ivec2& s : sizes) {
      const std::optional<glm::ivec2> p = place_one(s.x + gutter_, s.y + gutter_);
      if (!p) {
        shelves_ = shelves;
        top_ = top;
        return std::nullopt;
      }
      at.push_back(*p);
    }
    return at;
  }

 private:
  struct Shelf {
    int y, height, used;
  };
  std::optional<glm::ivec2> place_one(int w, int h) {
    if (w > page_ || h > page_) return std::nullopt;
    Shelf* best = nullptr;
    for (Shelf& s : shelves_)
      if (s.height >= h && s.used + w <= page_ && (!best || s.height < best->height)) best = &s;
    if (!best) {
      if (top_ + h > page_) return std::nullopt;
      shelves_.push_back({top_, h, 0});
      top_ += h;
      best = &shelves_.back();
    }
    const glm::ivec2 p(best->used, best->y);
    best->used += w;
    return p;
  }

  int page_, gutter_;
  int page_index_ = 0;
  std::vector<Shelf> shelves_;
  int top_ = 0;
};

}  // namespace farfield
