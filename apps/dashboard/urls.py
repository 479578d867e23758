from django.urls import path

from . import views

app_name = "dashboard"
urlpatterns = [
    path("", views.home, name="home"),
    path("clusters/", views.cluster_list, name="clusters"),
    path("clusters/<int:pk>/", views.cluster_detail, name="cluster"),
    path("applications/", views.application_list, name="applications"),
    path("applications/<int:pk>/", views.application_detail, name="application"),
    path("applications/generate/", views.application_generate, name="application-generate"),
    path("applications/<int:pk>/schedule/", views.application_schedule, name="application-schedule"),
    path("applications/<int:pk>/compare/", views.application_compare, name="application-compare"),
    path("schedules/", views.schedule_list, name="schedules"),
    path("schedules/<int:pk>/", views.schedule_detail, name="schedule"),
    path("schedules/<int:pk>/push/", views.schedule_push, name="schedule-push"),
    path("comparisons/", views.comparison_list, name="comparisons"),
    path("comparisons/<int:pk>/", views.comparison_detail, name="comparison"),
    path("devices/", views.device_list, name="devices"),
    path("devices/<slug:slug>/", views.device_detail, name="device"),
    path("jobs/", views.job_list, name="jobs"),
    path("jobs/<uuid:pk>/", views.job_detail, name="job"),
]
