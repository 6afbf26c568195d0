// Bullet's allocator: every object Bullet allocates (rigid bodies, broadphase proxies and tree
// nodes, contact manifolds, its arrays) comes from size classes whose blocks are recycled
// and never returned, so that the step, once the classes have grown to the plant's needs,
// asks the heap for nothing.
//
// The classes are multiples of 16 B, four to a doubling above 128 B (16, 32, ... 128, 160,
// 192, 224, 256, 320, ... 1 MiB), so a block over 128 B wastes at most a fifth of it: a rigid
// body (744 B) takes 768, a broadphase proxy (88 B) 96, a tree node (56 B) 64. A class grows
// by a quarter of its blocks so far (at least 8 blocks, at most about 4 MiB), in heap chunks
// of up to 512 B, several small blocks to a chunk: with its header a rigid body takes 784 B
// of the heap, a tree node 80.
//
// Each block starts with a 16-byte header naming its class. The functions are Bullet's
// aligned pair (btAlignedAllocSetCustomAligned), so Bullet does not pad each request for
// its own alignment: our blocks are 16-aligned, which is all Bullet asks for; a request for
// more, or for more than the largest class, goes to the heap with a header that says so
// (and counts as a heap request).
#include "engine/physics.h"

#include <LinearMath/btAlignedAllocator.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace plant::engine {

#if !defined(__SANITIZE_ADDRESS__)
namespace {

constexpr uint64_t kMark = 0x706c616e742d6274ULL;
struct alignas(16) BlockHeader {
    uint64_t mark;
    uint32_t cls;   // the class, or kHeap
    uint32_t back;  // a heap block: bytes from the heap's pointer to this header
};
static_assert(sizeof(BlockHeader) == 16);

// Class c's block size: 16 (c + 1) up to 128, then four steps per doubling.
constexpr size_t class_size(int c) {
    if (c < 8) return size_t(16) * size_t(c + 1);
    const int d = (c - 8) / 4, q = (c - 8) % 4;  // 128 << d, and a quarter of it q + 1 times
    return (size_t(128) << d) + (size_t(32) << d) * size_t(q + 1);
}
constexpr int kClasses = 8 + 4 * 13;  // up to 128 << 13 = 1 MiB
static_assert(class_size(kClasses - 1) == size_t(1) << 20);
constexpr uint32_t kHeap = ~uint32_t(0);

constexpr int size_class(size_t n) {
    if (n <= 128) return n == 0 ? 0 : int((n - 1) / 16);
    int d = 0;
    while ((size_t(256) << d) < n) ++d;                          // 128 << d < n <= 256 << d
    const size_t quarter = size_t(32) << d;
    const int q = int((n - (size_t(128) << d) + quarter - 1) / quarter) - 1;  // 0..3
    return 8 + 4 * d + q;
}

// The worlds step on several threads, and a block one thread took may be freed by another. Each
// thread recycles small blocks through lists of its own; a list that grows past 2 batches hands a
// batch to the shared list of its class (behind a spin lock), and an empty one takes a batch from
// there before the class grows from the heap. So no list grows without bound while another
// thread keeps asking the heap, and the lock is taken once per batch.
constexpr uint32_t kBatch = 64;
// Blocks of more than 512 B (rigid bodies, manifolds, arrays) go straight to the shared lists,
// so that no thread holds back a large block another one then takes from the heap.
constexpr size_t kLocalMax = 512;

struct alignas(64) Shared {
    std::atomic_flag busy;
    void* head = nullptr;
    uint64_t blocks = 0;  // blocks taken from the heap so far
};
Shared g_shared[kClasses];
std::atomic<uint64_t> g_heap_requests{0};  // times a class grew from the heap

class Hold {
public:
    explicit Hold(Shared& l) : l_(l) {
        while (l_.busy.test_and_set(std::memory_order_acquire)) {
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
        }
    }
    ~Hold() { l_.busy.clear(std::memory_order_release); }
    Hold(const Hold&) = delete;
    Hold& operator=(const Hold&) = delete;

private:
    Shared& l_;
};

void*& next_of(void* p) { return *static_cast<void**>(p); }

// Writes a block's header; returns the block.
void* stamp(void* at, uint32_t cls, uint32_t back) {
    auto* h = static_cast<BlockHeader*>(at);
    h->mark = kMark;
    h->cls = cls;
    h->back = back;
    return h + 1;
}

// Puts block p on the shared list of its class; that class's lock is held.
void push(Shared& s, void* p) {
    next_of(p) = s.head;
    s.head = p;
}

// A class grows by a quarter of its blocks so far (at least 8, at most about 4 MiB at once),
// allocated in chunks of up to 512 B (or of one block, if larger), whose blocks go onto the
// class's shared list; the lock of class c is held. Chunks this small fill the holes a
// compiler's freed memory leaves in the heap, which are resident anyway: chunks of 4 KiB
// left most of them empty, and the 1,000-bottle plant's process peaked 25 MiB higher.
// False when the heap has nothing.
constexpr size_t kChunk = 512;
bool grow_class(int c) {
    Shared& s = g_shared[c];
    const size_t step = sizeof(BlockHeader) + class_size(c);
    const uint64_t cap = std::max<uint64_t>(1, (uint64_t(4) << 20) / step);
    const uint64_t more = std::clamp<uint64_t>(s.blocks / 4, 8, cap);
    const uint64_t per = std::max<uint64_t>(1, kChunk / step);
    uint64_t made = 0;
    while (made < more) {
        const uint64_t n = std::min(per, more - made);
        auto* chunk = static_cast<char*>(std::malloc(size_t(n) * step));  // 16-aligned
        if (!chunk) break;
        for (uint64_t k = 0; k < n; ++k) push(s, stamp(chunk + size_t(k) * step, uint32_t(c), 0));
        made += n;
    }
    s.blocks += made;
    if (made) g_heap_requests.fetch_add(1, std::memory_order_relaxed);
    return made > 0;
}

// A block of class c from its shared list, which grows when it is empty; the lock of class c
// is held. Null when the heap has nothing.
void* pop_block(int c) {
    Shared& s = g_shared[c];
    if (!s.head && !grow_class(c)) return nullptr;
    void* p = s.head;
    s.head = next_of(p);
    return p;
}

struct Local {
    void* head[kClasses] = {};
    uint32_t count[kClasses] = {};
    // Moves up to n blocks from this list to the shared one.
    void give(int c, uint32_t n) {
        if (!head[c]) return;
        void* first = head[c];
        void* last = first;
        uint32_t k = 1;
        for (; k < n && next_of(last); ++k) last = next_of(last);
        head[c] = next_of(last);
        count[c] -= k;
        Hold hold(g_shared[c]);
        next_of(last) = g_shared[c].head;
        g_shared[c].head = first;
    }
    // Takes a batch from the shared list.
    void take(int c) {
        Hold hold(g_shared[c]);
        for (uint32_t k = 0; k < kBatch; ++k) {
            void* p = pop_block(c);
            if (!p) break;
            next_of(p) = head[c];
            head[c] = p;
            ++count[c];
        }
    }
    ~Local() {  // a thread that ends leaves its blocks to the others
        for (int c = 0; c < kClasses; ++c) give(c, count[c]);
    }
};
thread_local Local t_local;

constexpr int kLocalClasses = size_class(kLocalMax) + 1;

void* from_heap(size_t n, size_t alignment) {
    const size_t a = std::max<size_t>(alignment, alignof(BlockHeader));
    auto* raw = static_cast<char*>(std::malloc(sizeof(BlockHeader) + n + a));
    if (!raw) return nullptr;
    g_heap_requests.fetch_add(1, std::memory_order_relaxed);
    const auto at = (reinterpret_cast<uintptr_t>(raw) + sizeof(BlockHeader) + a - 1) & ~uintptr_t(a - 1);
    char* h = reinterpret_cast<char*>(at) - sizeof(BlockHeader);
    return stamp(h, kHeap, uint32_t(h - raw));
}

void* bullet_alloc(size_t n, int alignment) {
    if (alignment > int(alignof(BlockHeader)) || (alignment & (alignment - 1)) != 0 ||
        n > class_size(kClasses - 1))
        return from_heap(n, size_t(std::max(alignment, 1)));
    const int c = size_class(n);
    if (c < kLocalClasses) {
        Local& l = t_local;
        if (!l.head[c]) l.take(c);
        void* p = l.head[c];
        if (p) {
            l.head[c] = next_of(p);
            --l.count[c];
        }
        return p;
    }
    Hold hold(g_shared[c]);
    return pop_block(c);
}

void bullet_free(void* p) {
    if (!p) return;
    BlockHeader* h = static_cast<BlockHeader*>(p) - 1;
    // A block from before the pool was installed (there are none: it is installed before
    // main) would be Bullet's own, which keeps the heap's pointer just before it.
    if (h->mark != kMark) return std::free(static_cast<void**>(p)[-1]);
    if (h->cls == kHeap) return std::free(reinterpret_cast<char*>(h) - h->back);
    const int c = int(h->cls);
    if (c >= kLocalClasses) {
        Hold hold(g_shared[c]);
        return push(g_shared[c], p);
    }
    Local& l = t_local;
    next_of(p) = l.head[c];
    l.head[c] = p;
    if (++l.count[c] > 2 * kBatch) l.give(c, kBatch);
}

}  // namespace

bool install_bullet_pool() {
    btAlignedAllocSetCustomAligned(bullet_alloc, bullet_free);
    return true;
}
bool bullet_pool() { return true; }
uint64_t bullet_heap_requests() { return g_heap_requests.load(std::memory_order_relaxed); }
#else
// Sanitizer builds: Bullet uses the heap directly.
bool install_bullet_pool() { return false; }
bool bullet_pool() { return false; }
uint64_t bullet_heap_requests() { return 0; }
#endif

}  // namespace plant::engine
