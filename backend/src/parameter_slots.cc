#include <omnidso/backend/parameter_slots.hpp>
#include <omnidso/core/error.hpp>
#include <string>

namespace omnidso {

ParameterSlots::ParameterSlots(int capacity)
    : capacity_(capacity), in_use_(capacity > 0 ? static_cast<size_t>(capacity) : 0, false) {
  if (capacity <= 0)
    throw Error("ParameterSlots: capacity must be positive (got " + std::to_string(capacity) + ")");
  storage_.reset(new double[static_cast<size_t>(capacity)]);  // uninitialised: untouched pages
}

double* ParameterSlots::acquire() {
  int index;
  if (!released_.empty()) {
    index = released_.top();
    released_.pop();
  } else if (next_unused_ < capacity_) {
    index = next_unused_++;
  } else {
    throw Error("ParameterSlots: all " + std::to_string(capacity_) +
                " slots are in use (raise window.max_points)");
  }
  in_use_[static_cast<size_t>(index)] = true;
  storage_[static_cast<size_t>(index)] = 0.0;
  return &storage_[static_cast<size_t>(index)];
}

void ParameterSlots::release(double* slot) {
  const double* base = storage_.get();
  if (slot < base || slot >= base + capacity_)
    throw Error("ParameterSlots::release: the pointer is not a slot of this array");
  const auto index = static_cast<size_t>(slot - base);
  if (!in_use_[index]) throw Error("ParameterSlots::release: slot " + std::to_string(index) + " is not in use");
  in_use_[index] = false;
  released_.push(static_cast<int>(index));
}

}  // namespace omnidso
