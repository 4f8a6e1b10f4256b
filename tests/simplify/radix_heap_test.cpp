// The collapse queue (lib/src/simplify/radix_heap.h), with 1-bit digits (the parallel phase's
// queues) and 8-bit digits (the serial queue): blocks chained per bucket, against a model that keeps each bucket of a one-bucket-per-bit radix heap in one
// growing vector (the layout before the blocks and the digits), through random pushes, pops,
// refills, sheds, copies and hand-overs long enough to chain many blocks.
// The engine's results depend on the exact order of ties, so the model checks that order, and
// a multiset checks that every pop is a smallest key.
#include "radix_heap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace visimp::detail {
namespace {

struct Item {
  std::uint32_t key;
  std::uint32_t id;
  bool operator==(const Item& o) const { return key == o.key && id == o.id; }
};

// The same queue with every bucket one vector: items enter at the back, bucket 0 pops from
// the back, a refill moves a bucket's items front to back; assigned items are spread from
// their smallest key at the next push or pop.
class VectorRadixHeap {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  // Returns the key as queued (clamped to the last popped).
  std::uint32_t push(Item item) {
    if (!bulk_.empty()) spread();
    if (item.key < last_) item.key = last_;
    buckets_[bucket_of(item.key)].push_back(item);
    ++size_;
    return item.key;
  }
  void assign(std::vector<Item> items) {
    for (auto& b : buckets_) b.clear();
    last_ = 0;
    size_ = items.size();
    bulk_ = std::move(items);
  }
  Item pop() {
    if (buckets_[0].empty()) refill();
    const Item item = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return item;
  }
  bool pop_at_most(std::uint32_t limit, Item& out) {
    if (size_ == 0) return false;
    if (buckets_[0].empty()) refill();
    if (last_ > limit) return false;
    out = pop();
    return true;
  }
  std::uint32_t min_key() {
    if (buckets_[0].empty()) refill();
    return last_;
  }
  void take_all(std::vector<Item>& into) {
    into.insert(into.end(), bulk_.begin(), bulk_.end());
    bulk_.clear();
    for (auto& b : buckets_) {
      into.insert(into.end(), b.begin(), b.end());
      b.clear();
    }
    size_ = 0;
    last_ = 0;
  }
  template <class Pred>
  void remove_if(Pred drop) {
    bulk_.erase(std::remove_if(bulk_.begin(), bulk_.end(), drop), bulk_.end());
    size_ = bulk_.size();
    for (auto& b : buckets_) {
      b.erase(std::remove_if(b.begin(), b.end(), drop), b.end());
      size_ += b.size();
    }
  }

 private:
  int bucket_of(std::uint32_t key) const { return key == last_ ? 0 : 32 - __builtin_clz(key ^ last_); }
  void refill() {
    if (!bulk_.empty()) return spread();
    int i = 1;
    while (buckets_[i].empty()) ++i;
    std::vector<Item> moving;
    moving.swap(buckets_[i]);
    spread_from_smallest(moving);
  }
  void spread() {
    std::vector<Item> moving;
    moving.swap(bulk_);
    spread_from_smallest(moving);
  }
  void spread_from_smallest(const std::vector<Item>& moving) {
    last_ = std::min_element(moving.begin(), moving.end(), [](const Item& a, const Item& b) { return a.key < b.key; })
                ->key;
    for (const Item& item : moving) buckets_[bucket_of(item.key)].push_back(item);
  }
  std::vector<Item> bulk_;
  std::array<std::vector<Item>, 33> buckets_;
  std::uint32_t last_ = 0;
  std::size_t size_ = 0;
};

// Every test runs with each digit width the engine uses: the pop order must not depend on it.
template <class Heap>
class RadixHeapDigits : public ::testing::Test {};
struct DigitsName {
  template <class Heap>
  static std::string GetName(int) {
    return std::is_same_v<Heap, RadixHeap<Item, std::vector<Item>, 1>> ? "BitDigits" : "ByteDigits";
  }
};
using DigitWidths = ::testing::Types<RadixHeap<Item, std::vector<Item>, 1>, RadixHeap<Item, std::vector<Item>, 8>>;
TYPED_TEST_SUITE(RadixHeapDigits, DigitWidths, DigitsName);

// Runs `steps` random operations on both queues; keys rise slowly like collapse costs, with
// some below the last popped (clamped), many ties and now and then a huge one.
template <class Heap>
void run_against_model(Heap& heap, VectorRadixHeap& model, std::mt19937& rng, int steps, std::uint32_t& next_id) {
  std::multiset<std::uint32_t> keys;  // the model's keys, clamped as pushed
  std::uint32_t floor = 0;            // about the last popped key, for drawing keys
  for (VectorRadixHeap drained = model; !drained.empty();) keys.insert(drained.pop().key);
  auto random_key = [&] {
    const std::uint32_t r = std::uint32_t(rng()) % 100;
    if (r < 10) return floor;                                // a tie with the last popped
    if (r < 15) return floor > 50 ? floor - 50 : 0u;         // below it: clamped
    if (r < 17) return std::uint32_t(0x7f800000u);           // a refused edge's key
    return floor + std::uint32_t(std::uint32_t(rng()) % (r < 80 ? 64 : 1u << 20));
  };
  for (int step = 0; step < steps; ++step) {
    const std::uint32_t op = std::uint32_t(rng()) % 100;
    if (op < 55 || model.empty()) {
      Item item{random_key(), next_id++};
      heap.push(item);
      keys.insert(model.push(item));
    } else if (op < 90) {
      ASSERT_EQ(heap.min_key(), model.min_key());
      const Item got = heap.pop(), want = model.pop();
      ASSERT_EQ(got, want) << "step " << step;
      ASSERT_EQ(got.key, *keys.begin()) << "not a smallest key at step " << step;
      keys.erase(keys.begin());
      floor = got.key;
    } else if (op < 97) {
      const std::uint32_t limit = floor + std::uint32_t(std::uint32_t(rng()) % 128);
      Item got{}, want{};
      const bool a = heap.pop_at_most(limit, got), b = model.pop_at_most(limit, want);
      ASSERT_EQ(a, b);
      if (a) {
        ASSERT_EQ(got, want);
        keys.erase(keys.find(got.key));
        floor = got.key;
      }
    } else {
      const std::uint32_t modulus = 2 + std::uint32_t(rng()) % 5;
      auto drop = [&](const Item& i) { return i.id % modulus == 0; };
      heap.remove_if(drop);
      model.remove_if(drop);
      std::vector<Item> left;
      Heap copy = heap;  // the copy's order is the heap's
      VectorRadixHeap model_copy = model;
      keys.clear();
      while (!model_copy.empty()) {
        const Item i = model_copy.pop();
        ASSERT_EQ(copy.pop(), i);
        keys.insert(i.key);
      }
      ASSERT_TRUE(copy.empty());
    }
    ASSERT_EQ(heap.size(), model.size());
  }
}

TYPED_TEST(RadixHeapDigits, SameOrderAsOneVectorPerBucket) {
  std::mt19937 rng(7);
  std::uint32_t next_id = 0;
  TypeParam heap;
  VectorRadixHeap model;
  run_against_model(heap, model, rng, 60000, next_id);
  // Drained: both end together, in the same order.
  while (!model.empty()) ASSERT_EQ(heap.pop(), model.pop());
  EXPECT_TRUE(heap.empty());
}

TYPED_TEST(RadixHeapDigits, AssignedItemsAreTheOldestOfTheTopBucket) {
  std::mt19937 rng(11);
  std::uint32_t next_id = 0;
  std::vector<Item> initial;
  for (int i = 0; i < 50000; ++i) initial.push_back({std::uint32_t(std::uint32_t(rng()) % 5000), next_id++});
  TypeParam heap;
  VectorRadixHeap model;
  heap.assign(std::vector<Item>(initial));
  model.assign(initial);
  // Pushes before the first pop land beside the assigned items, some in the top bucket.
  for (int i = 0; i < 1000; ++i) {
    const Item item{i % 3 == 0 ? 0x80000000u + std::uint32_t(i) : std::uint32_t(std::uint32_t(rng()) % 5000), next_id++};
    heap.push(item);
    model.push(item);
  }
  run_against_model(heap, model, rng, 30000, next_id);
  while (!model.empty()) ASSERT_EQ(heap.pop(), model.pop());
}

// The parallel phase fills each partition's queue with assign_spread from a scratch array it
// then frees: the queue must pop in the order assign() gives, through pushes and refills.
TYPED_TEST(RadixHeapDigits, AssignSpreadPopsAsAssignDoes) {
  std::mt19937 rng(13);
  std::uint32_t next_id = 0;
  std::vector<Item> initial;
  for (int i = 0; i < 40000; ++i) initial.push_back({std::uint32_t(std::uint32_t(rng()) % 70000) + 900, next_id++});
  TypeParam heap;
  VectorRadixHeap model;
  heap.push({1, next_id++});  // emptied by the assignment
  heap.assign_spread(initial);
  model.assign(initial);
  EXPECT_EQ(heap.size(), initial.size());
  EXPECT_EQ(heap.min_key(), std::min_element(initial.begin(), initial.end(), [](Item a, Item b) { return a.key < b.key; })->key);
  run_against_model(heap, model, rng, 30000, next_id);
  while (!model.empty()) ASSERT_EQ(heap.pop(), model.pop());
  // Nothing to spread: empty, and later pushes are not clamped to a key no item had.
  heap.assign_spread(std::vector<Item>{});
  EXPECT_TRUE(heap.empty());
  heap.push({3, 1});
  EXPECT_EQ(heap.pop(), (Item{3, 1}));
}

TYPED_TEST(RadixHeapDigits, TakeAllHandsOverEqualKeysInPushOrderAndEmpties) {
  std::mt19937 rng(3);
  std::uint32_t next_id = 0;
  TypeParam heap;
  VectorRadixHeap model;
  heap.assign(std::vector<Item>{{5, next_id++}, {1u << 30, next_id++}});
  model.assign({{5, 0}, {1u << 30, 1}});
  run_against_model(heap, model, rng, 30000, next_id);
  std::vector<Item> got{{1, 999999}}, want{{1, 999999}};  // appended after what is there
  heap.take_all(got);
  model.take_all(want);
  // Buckets differ between the two, so the hand-over's order may too, except among equal keys
  // (what a queue assigned from it pops by): sorted stably by key, the two are the same.
  auto by_key = [](const Item& a, const Item& b) { return a.key < b.key; };
  ASSERT_EQ(got.front(), (Item{1, 999999}));
  std::stable_sort(got.begin() + 1, got.end(), by_key);
  std::stable_sort(want.begin() + 1, want.end(), by_key);
  EXPECT_EQ(got, want);
  EXPECT_GT(got.size(), 100u);
  EXPECT_TRUE(heap.empty());
  // Usable again after the hand-over, from key 0.
  heap.push({0, 1});
  EXPECT_EQ(heap.min_key(), 0u);
  EXPECT_EQ(heap.pop(), (Item{0, 1}));
}

TYPED_TEST(RadixHeapDigits, MovedAndCopiedHeapsKeepTheirItems) {
  std::mt19937 rng(5);
  std::uint32_t next_id = 0;
  TypeParam heap;
  VectorRadixHeap model;
  run_against_model(heap, model, rng, 20000, next_id);
  std::vector<TypeParam> lanes;
  lanes.push_back(heap);                // a copy
  lanes.push_back(std::move(heap));     // the original, moved
  lanes.resize(40);                     // moved again as the vector grows
  while (!model.empty()) {
    const Item want = model.pop();
    ASSERT_EQ(lanes[0].pop(), want);
    ASSERT_EQ(lanes[1].pop(), want);
  }
  EXPECT_TRUE(lanes[0].empty() && lanes[1].empty());
}

}  // namespace
}  // namespace visimp::detail
