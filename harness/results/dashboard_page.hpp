#pragma once
// The fixed parts of the history page (dashboard.cpp puts the header and the data around them):
// its style, its filter and legend bar, and its script, plain JavaScript over Chart.js 3 that
// draws one chart per series of the embedded JSON and sets <body data-drawn="N"> once N
// charts show their medians (what the browser test waits for).
namespace suite::dashboard_detail {

extern const char* const page_style;
extern const char* const page_controls;
extern const char* const page_script;

}  // namespace suite::dashboard_detail
