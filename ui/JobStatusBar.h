#pragma once
// The running jobs in the main window's status bar: one compact progress bar (titled, with the
// job's fraction when it reports one) and Cancel button per job, so a mesh preview and a flow
// solve can run side by side; the job's status line goes to the status bar's message, and its
// end ("done", "cancelled", "failed: why") too. GUI thread only.
#include <QHash>
#include <QWidget>

class QHBoxLayout;
class QStatusBar;

namespace aero::ui {

class Job;
class JobRunner;

class JobStatusBar : public QWidget {
    Q_OBJECT

  public:
    JobStatusBar(JobRunner* jobs, QStatusBar* bar, QWidget* parent = nullptr);
    /// Jobs shown now.
    int shownJobs() const { return static_cast<int>(items_.size()); }

  private:
    void add(Job* job);
    void remove(Job* job);

    JobRunner* jobs_;
    QStatusBar* bar_;
    QHBoxLayout* layout_;
    QHash<int, QWidget*> items_;  // by job id
};

}  // namespace aero::ui
