// Chunked: an array that grows without moving what it holds. Items live in chunks of
// 2^Bits, each allocated once at its full size and filled in place, so growing never copies
// the items already stored (a doubling vector holds its old and new blocks side by side
// while it moves them: three times what it stores, at the moment the solver is largest),
// references to items stay valid as others are added, and the memory a chunk takes is
// touched only as it fills. Indices are dense, as a vector's: the nodes of the hierarchy and
// the links are both kept so (hierarchy.h, link_store.h).
#pragma once
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace radiosity {

template <class T, size_t Bits>
class Chunked {
public:
    static constexpr size_t kChunk = size_t(1) << Bits;

    Chunked() = default;
    Chunked(const Chunked& o) : size_(o.size_) {
        chunks_.reserve(o.chunks_.size());
        for (const std::vector<T>& c : o.chunks_) {
            chunks_.emplace_back();
            chunks_.back().reserve(kChunk);
            chunks_.back().insert(chunks_.back().end(), c.begin(), c.end());
        }
    }
    Chunked& operator=(const Chunked& o) {
        if (this != &o) *this = Chunked(o);
        return *this;
    }
    Chunked(Chunked&&) noexcept = default;
    Chunked& operator=(Chunked&&) noexcept = default;

    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    T& operator[](size_t i) { return chunks_[i >> Bits][i & (kChunk - 1)]; }
    const T& operator[](size_t i) const { return chunks_[i >> Bits][i & (kChunk - 1)]; }
    T& back() { return (*this)[size_ - 1]; }
    const T& back() const { return (*this)[size_ - 1]; }

    void push_back(T item) {
        if ((size_ & (kChunk - 1)) == 0) {
            chunks_.emplace_back();
            chunks_.back().reserve(kChunk);
        }
        chunks_.back().push_back(std::move(item));
        ++size_;
    }
    void clear() {
        chunks_.clear();
        size_ = 0;
    }
    // Bytes held once `more` items are added: whole chunks (the memory estimate's view).
    double bytes(size_t more = 0) const {
        const size_t chunks = std::max(chunks_.size(), (size_ + more + kChunk - 1) / kChunk);
        return double(chunks) * (double(kChunk) * double(sizeof(T)) + double(sizeof(std::vector<T>)));
    }

    template <class Store, class Item>
    class Iter {
    public:
        Iter(Store* s, size_t i) : s_(s), i_(i) {}
        Item& operator*() const { return (*s_)[i_]; }
        Item* operator->() const { return &(*s_)[i_]; }
        Iter& operator++() {
            ++i_;
            return *this;
        }
        bool operator==(const Iter& o) const { return i_ == o.i_; }
        bool operator!=(const Iter& o) const { return i_ != o.i_; }

    private:
        Store* s_;
        size_t i_;
    };
    using iterator = Iter<Chunked, T>;
    using const_iterator = Iter<const Chunked, const T>;
    iterator begin() { return {this, 0}; }
    iterator end() { return {this, size_}; }
    const_iterator begin() const { return {this, 0}; }
    const_iterator end() const { return {this, size_}; }

private:
    // Each chunk's capacity is reserved when it is made (a copy's too): push_back never
    // reallocates one.
    std::vector<std::vector<T>> chunks_;
    size_t size_ = 0;
};

}  // namespace radiosity
