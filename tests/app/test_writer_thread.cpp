// app::WriterThread, the queue and thread behind maps.rawlog and pndt-live's recording:
// order, back-pressure, the first error stops the writing and is kept, close() drains.
#include <gtest/gtest.h>
#include <pndt/app/writer_thread.h>

#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

using pndt::app::WriterThread;
using namespace std::chrono_literals;

TEST(WriterThread, WritesEveryItemInQueueOrderBeforeCloseReturns)
{
    std::vector<int> written;  // only the writer thread touches it until close() returns
    WriterThread<int> w(4, [&](int& i) { written.push_back(i); });
    for (int i = 0; i < 1000; ++i) ASSERT_TRUE(w.push(i));
    w.close();
    ASSERT_EQ(written.size(), 1000u);
    for (int i = 0; i < 1000; ++i) EXPECT_EQ(written[size_t(i)], i);
    EXPECT_EQ(w.error(), nullptr);
    EXPECT_GE(w.secondsWriting(), 0.0);
    w.close();  // idempotent
}

TEST(WriterThread, APushWaitsWhileTheQueueIsFull)
{
    std::promise<void> entered, go;
    std::shared_future<void> gate = go.get_future().share();
    bool first = true;  // the writer thread's
    std::atomic<int> written{0};
    WriterThread<int> w(2, [&](int&) {
        if (first) entered.set_value();
        first = false;
        gate.wait();  // the disk is slow
        ++written;
    });
    ASSERT_TRUE(w.push(0));
    entered.get_future().wait();  // item 0 left the queue; the writer waits at the gate
    ASSERT_TRUE(w.push(1));
    ASSERT_TRUE(w.push(2));  // the queue at its bound of 2
    std::atomic<bool> returned{false};
    std::thread producer([&] {
        EXPECT_TRUE(w.push(3));
        returned = true;
    });
    std::this_thread::sleep_for(100ms);
    EXPECT_FALSE(returned) << "a push returned with the queue full";
    go.set_value();  // the disk catches up
    producer.join();
    EXPECT_TRUE(returned);
    w.close();
    EXPECT_EQ(written.load(), 4);
}

TEST(WriterThread, TheFirstErrorStopsTheWritingIsKeptAndTheRestIsDrained)
{
    std::vector<int> written;
    WriterThread<int> w(8, [&](int& i) {
        if (i == 3) throw std::runtime_error("cannot write rec.rawlog: No space left on device");
        if (i == 5) throw std::logic_error("a later error");
        written.push_back(i);
    });
    // Pushes go on until the writer has met the error; from then on they are refused.
    bool refused = false;
    for (int i = 0; i < 100000 && !refused; ++i) refused = !w.push(i);
    EXPECT_TRUE(refused);
    w.close();
    EXPECT_EQ(written, (std::vector<int>{0, 1, 2}));
    ASSERT_NE(w.error(), nullptr);
    try
    {
        w.rethrowError();
        ADD_FAILURE() << "no error rethrown";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_STREQ(e.what(), "cannot write rec.rawlog: No space left on device");  // the first, not a later one
    }
    EXPECT_FALSE(w.push(7));
}
