#pragma once
// One array of an MPM state: a pointer and a length, backed either by the point's Arena (placed:
// the harness's policy decided where its pages live, the state's set-up touched them first from
// the computing threads, and the memory is the arena's, freed with it) or by storage of its own
// (a state built without an arena, as `suite mpm` and the tests build them, and every copy).
// The loops take data() once, as a raw pointer, so neither kind costs them anything.
//
// Placed storage cannot change its length, and it is never swapped for other storage: the
// reorderings write their result back into it (reorder.cpp), so that its pages stay where the
// policy put them. A copy is plain heap memory; assigning to a placed array of the same length
// copies into its pages.
#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

namespace suite::mpm {

template <class T>
class Array {
public:
    using value_type = T;
    using size_type = std::size_t;
    using difference_type = std::ptrdiff_t;
    using reference = T&;
    using const_reference = const T&;
    using pointer = T*;
    using const_pointer = const T*;
    using iterator = T*;
    using const_iterator = const T*;

    Array() = default;
    explicit Array(std::size_t n, const T& value = T{}) : own_(n, value) { adopt(); }
    explicit Array(std::vector<T> v) : own_(std::move(v)) { adopt(); }
    // `n` objects at `p` in an Arena (which owns them, and must outlive this array).
    static Array placed(T* p, std::size_t n) {
        Array a;
        a.data_ = p;
        a.size_ = n;
        a.placed_ = true;
        return a;
    }

    Array(const Array& o) : own_(o.begin(), o.end()) { adopt(); }
    Array(Array&& o) noexcept : own_(std::move(o.own_)), data_(o.data_), size_(o.size_), placed_(o.placed_) {
        o.forget();
    }
    Array& operator=(const Array& o) {
        if (this == &o) return *this;
        if (placed_ && size_ == o.size_)
            std::copy(o.begin(), o.end(), data_);
        else {
            own_.assign(o.begin(), o.end());
            adopt();
        }
        return *this;
    }
    Array& operator=(Array&& o) noexcept {
        if (this == &o) return *this;
        own_ = std::move(o.own_);  // a vector's move keeps its buffer, so data_ stays valid
        data_ = o.data_, size_ = o.size_, placed_ = o.placed_;
        o.forget();
        return *this;
    }

    T* data() { return data_; }
    const T* data() const { return data_; }
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    T& operator[](std::size_t i) { return data_[i]; }
    const T& operator[](std::size_t i) const { return data_[i]; }
    T* begin() { return data_; }
    T* end() { return data_ + size_; }
    const T* begin() const { return data_; }
    const T* end() const { return data_ + size_; }
    // Whether the storage is an Arena's.
    bool placed() const { return placed_; }

    // Only to the length a placed array already has (then a no-op); own storage as a vector.
    void resize(std::size_t n) {
        if (n == size_) return;
        if (placed_) throw std::logic_error("an MPM array placed in the arena cannot change its length");
        own_.resize(n);
        adopt();
    }
    void assign(std::size_t n, const T& value) {
        resize(n);
        std::fill(begin(), end(), value);
    }
    // Gives own storage to `other` and takes its own: only between two arrays that own theirs.
    void swap(std::vector<T>& other) {
        if (placed_) throw std::logic_error("an MPM array placed in the arena is written back, never swapped");
        own_.swap(other);
        adopt();
    }

    operator std::vector<T>() const { return std::vector<T>(begin(), end()); }
    friend bool operator==(const Array& a, const Array& b) {
        return std::equal(a.begin(), a.end(), b.begin(), b.end());
    }
    friend bool operator==(const Array& a, const std::vector<T>& b) {
        return std::equal(a.begin(), a.end(), b.begin(), b.end());
    }

private:
    void adopt() {
        data_ = own_.data();
        size_ = own_.size();
        placed_ = false;
    }
    void forget() {
        own_.clear();
        data_ = nullptr;
        size_ = 0;
        placed_ = false;
    }

    std::vector<T> own_;
    T* data_ = nullptr;
    std::size_t size_ = 0;
    bool placed_ = false;
};

}  // namespace suite::mpm
