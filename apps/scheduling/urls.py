from django.urls import path

from . import live, views

app_name = "scheduling"
urlpatterns = [
    path("applications/<int:pk>/schedule/", views.application_schedule, name="application-schedule"),
    path("applications/<int:pk>/compare/", views.application_compare, name="application-compare"),
    path("schedules/", views.schedule_list, name="schedules"),
    path("schedules/<int:pk>/", views.schedule_detail, name="schedule"),
    path("schedules/<int:pk>/live/", live.schedule_live, name="schedule-live"),
    path("schedules/<int:pk>/push/", views.schedule_push, name="schedule-push"),
    path("comparisons/", views.comparison_list, name="comparisons"),
    path("comparisons/<int:pk>/", views.comparison_detail, name="comparison"),
]
