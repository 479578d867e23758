from django.urls import path

from . import views

app_name = "verification"
urlpatterns = [
    path("", views.overview, name="overview"),
    path("simulate/", views.simulate, name="simulate"),
    path("assertions/<int:pk>/", views.assertion_detail, name="assertion"),
    path("runs/<int:pk>/", views.run_detail, name="run"),
    path("simulations/<uuid:series>/", views.series_detail, name="series"),
]
