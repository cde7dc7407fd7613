// A growable array of plain numbers that grows and shrinks with realloc: for the large arrays of
// the contact set, which a pass opens gaps in and grows in place. A std::vector copies itself
// into new storage to grow, so for a moment it holds its old and its new elements (for the
// sub-contacts' points, 24 B more per sub-contact at the peak of a settling model's memory);
// realloc of a block the allocator has mapped on its own (above M_MMAP_THRESHOLD, memory.cpp)
// moves the mapping instead, and touches no page. Elements are plain numbers or Eigen's
// fixed-size vectors of them (bytes and nothing else), copied as bytes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <new>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

namespace odec {

template <class T>
struct IsPlainNumbers : std::is_trivially_copyable<T> {};
template <class S, int R, int C, int O, int MR, int MC>
struct IsPlainNumbers<Eigen::Matrix<S, R, C, O, MR, MC>>
    : std::integral_constant<bool, std::is_arithmetic_v<S> && R != Eigen::Dynamic && C != Eigen::Dynamic> {};

template <class T>
class PodArray {
    static_assert(IsPlainNumbers<T>::value, "PodArray holds plain numbers only");
    static_assert(alignof(T) <= alignof(std::max_align_t), "malloc's alignment must do");

public:
    using value_type = T;
    using size_type = std::size_t;
    using iterator = T*;
    using const_iterator = const T*;
    using reference = T&;
    using const_reference = const T&;

    PodArray() = default;
    explicit PodArray(size_type n) { resize(n); }
    PodArray(size_type n, const T& v) { assign(n, v); }
    PodArray(std::initializer_list<T> l) { assign(l.begin(), l.end()); }
    template <class It, class = decltype(*std::declval<It>())>
    PodArray(It first, It last) { assign(first, last); }
    PodArray(const PodArray& o) { assign(o.begin(), o.end()); }
    PodArray(PodArray&& o) noexcept : p_(o.p_), n_(o.n_), cap_(o.cap_) { o.p_ = nullptr, o.n_ = o.cap_ = 0; }
    PodArray& operator=(const PodArray& o) {
        if (this != &o) assign(o.begin(), o.end());
        return *this;
    }
    PodArray& operator=(PodArray&& o) noexcept {
        PodArray(std::move(o)).swap(*this);
        return *this;
    }
    ~PodArray() { std::free(p_); }

    size_type size() const { return n_; }
    size_type capacity() const { return cap_; }
    bool empty() const { return n_ == 0; }
    T* data() { return p_; }
    const T* data() const { return p_; }
    T& operator[](size_type i) { return p_[i]; }
    const T& operator[](size_type i) const { return p_[i]; }
    T& front() { return p_[0]; }
    const T& front() const { return p_[0]; }
    T& back() { return p_[n_ - 1]; }
    const T& back() const { return p_[n_ - 1]; }
    T* begin() { return p_; }
    T* end() { return p_ + n_; }
    const T* begin() const { return p_; }
    const T* end() const { return p_ + n_; }
    const T* cbegin() const { return p_; }
    const T* cend() const { return p_ + n_; }

    // Capacity for n elements; nothing is touched beyond what is held.
    void reserve(size_type n) {
        if (n > cap_) reallocate(n);
    }
    // The spare capacity given back (in place).
    void shrink_to_fit() {
        if (cap_ > n_) reallocate(n_);
    }
    void clear() { n_ = 0; }
    // New elements are zero bytes (value-initialised numbers, zero vectors).
    void resize(size_type n) {
        const size_type p = n_;
        resize_for_overwrite(n);
        if (n > p) std::memset(static_cast<void*>(p_ + p), 0, (n - p) * sizeof(T));
    }
    void resize(size_type n, const T& v) {
        const size_type p = n_;
        resize_for_overwrite(n);
        std::fill(p_ + std::min(p, n), p_ + n, v);
    }
    // n elements, the new ones not set (the caller writes them before reading): their pages are
    // not touched.
    void resize_for_overwrite(size_type n) {
        if (n > cap_) reallocate(std::max(n, grown()));
        n_ = n;
    }
    void assign(size_type n, const T& v) {
        n_ = 0;
        resize(n, v);
    }
    template <class It, class = decltype(*std::declval<It>())>
    void assign(It first, It last) {
        const size_type n = static_cast<size_type>(std::distance(first, last));
        if (n > cap_) reallocate(n);
        std::copy(first, last, p_);
        n_ = n;
    }
    void push_back(const T& v) {
        if (n_ == cap_) {
            const T copy = v; // v may be an element of this array
            reallocate(grown());
            p_[n_++] = copy;
            return;
        }
        p_[n_++] = v;
    }
    template <class... A>
    T& emplace_back(A&&... a) {
        push_back(T(std::forward<A>(a)...));
        return back();
    }
    void pop_back() { --n_; }
    // [first, last) of another array or range appended.
    template <class It>
    void append(It first, It last) {
        const size_type k = static_cast<size_type>(std::distance(first, last));
        if (n_ + k > cap_) reallocate(std::max(n_ + k, grown()));
        std::copy(first, last, p_ + n_);
        n_ += k;
    }
    void swap(PodArray& o) noexcept {
        std::swap(p_, o.p_);
        std::swap(n_, o.n_);
        std::swap(cap_, o.cap_);
    }
    friend void swap(PodArray& a, PodArray& b) noexcept { a.swap(b); }
    friend bool operator==(const PodArray& a, const PodArray& b) {
        return a.n_ == b.n_ && std::equal(a.begin(), a.end(), b.begin());
    }
    friend bool operator!=(const PodArray& a, const PodArray& b) { return !(a == b); }

private:
    size_type grown() const { return std::max<size_type>(8, cap_ + cap_ / 2); }
    void reallocate(size_type n) {
        if (n == 0) {
            std::free(p_);
            p_ = nullptr;
            cap_ = 0;
            return;
        }
        if (n > static_cast<size_type>(PTRDIFF_MAX) / sizeof(T)) throw std::bad_alloc();
        void* q = std::realloc(static_cast<void*>(p_), n * sizeof(T));
        if (!q) throw std::bad_alloc(); // p_ still holds the elements
        p_ = static_cast<T*>(q);
        cap_ = n;
    }

    T* p_ = nullptr;
    size_type n_ = 0, cap_ = 0;
};

} // namespace odec
