#pragma once
// What the runner reads around every repetition: started just before the clock and stopped just
// after it, at the same points for every instrument. An instrument that measures nothing here is
// an object too (a null object, with its reason elsewhere), so the timed loop has no `if`.
namespace suite {

class RepetitionInstrument {
public:
    virtual ~RepetitionInstrument() = default;
    virtual void start() = 0;
    // The repetition is over; it took `seconds` by the clock (for rates such as watts).
    virtual void stop(double seconds) = 0;

protected:
    RepetitionInstrument() = default;
    RepetitionInstrument(const RepetitionInstrument&) = default;
    RepetitionInstrument& operator=(const RepetitionInstrument&) = default;
    RepetitionInstrument(RepetitionInstrument&&) = default;
    RepetitionInstrument& operator=(RepetitionInstrument&&) = default;
};

}  // namespace suite
