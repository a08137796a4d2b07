// MessageBacklog: the bounded queue between a subscription and the thread that handles its
// messages, counting every message it drops.
//
// roscpp's own subscriber queue drops its oldest message silently when full; the node therefore
// takes each message off roscpp's queue at once (a cheap callback that only calls push()) and
// keeps its own bounded backlog, in which a drop is counted where it happens.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace se3_interpolation
{
/// A first-in first-out queue of at most `capacity` messages handled one at a time, in order,
/// by one worker thread. push() never blocks: when the backlog is full, the oldest waiting
/// message is dropped (as roscpp's subscriber queue does) and counted.
template <class Message>
class MessageBacklog
{
public:
  using Handler = std::function<void(const Message&)>;

  /// Starts the worker, which calls `handler` for each message; `handler` must not throw.
  MessageBacklog(std::size_t capacity, Handler handler)
    : capacity_(capacity == 0 ? 1 : capacity), handler_(std::move(handler)), worker_([this] { run(); })
  {
  }

  /// Stops the worker after the message it handles now; waiting messages are discarded.
  ~MessageBacklog()
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
    worker_.join();
  }

  MessageBacklog(const MessageBacklog&) = delete;
  MessageBacklog& operator=(const MessageBacklog&) = delete;

  /// Queues `message`; returns true when the oldest waiting message was dropped to make room.
  bool push(Message message)
  {
    bool dropped = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (waiting_.size() >= capacity_)
      {
        waiting_.pop_front();
        ++dropped_;
        dropped = true;
      }
      waiting_.push_back(std::move(message));
    }
    changed_.notify_all();
    return dropped;
  }

  /// Messages dropped so far.
  std::uint64_t dropped() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

private:
  void run()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    while (true)
    {
      changed_.wait(lock, [this] { return stopping_ || !waiting_.empty(); });
      if (stopping_)
        return;
      Message message = std::move(waiting_.front());
      waiting_.pop_front();
      lock.unlock();
      handler_(message);
      // Released before the next wait: a handled message is not kept alive by the worker.
      message = Message();
      lock.lock();
    }
  }

  const std::size_t capacity_;
  const Handler handler_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Message> waiting_;
  std::uint64_t dropped_ = 0;
  bool stopping_ = false;
  std::thread worker_;  ///< last: started once every other member is initialised
};

}  // namespace se3_interpolation
